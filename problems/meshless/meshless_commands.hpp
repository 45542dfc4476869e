#pragma once
// The verbs of the `meshless` scene kind (docs/meshless.md, "Scenes"), each writing into
// out_dir: simulate (static equilibrium: report.json, nodes.vtu, samples.vtu), modes (modal
// analysis with Rayleigh damping ratios, modes.vtu, and warped modal dynamics under the scene's
// modes.force: frames/*.vtu and result.pvd), gradcheck (Taylor test of the inverse section's
// design functional: gradcheck.json) and run (the optimizer: report.json, samples.vtu at the
// best design).
#include <Eigen/Core>
#include <iosfwd>
#include <optional>
#include <string>

namespace tailor {

class SceneNode;

struct MeshlessVerbOptions {
  std::string name;        // the scene's name in the outputs
  std::string directory;   // relative paths in the scene start here
  std::string out_dir;
  std::optional<unsigned> seed;  // gradcheck
  bool hessian = false;          // gradcheck
  int count = 0;                 // modes: 0 = the scene's modes.count
  std::ostream* progress = nullptr;  // run: one line per iteration
};

// Each returns success (converged, passed); SceneError for bad scenes.
bool simulate_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);
bool modes_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);

// The modes verb's results as arrays (Python's modes()), besides its files: frequencies [Hz],
// eigenvalues and Rayleigh damping ratios of the elastic modes, and each mode's MLS displacement
// at the nodes (node_modes, 3 n x k, interleaved: not the coefficients, see meshless_fields.hpp)
// and at the samples (sample_modes, 3 m x k).
struct MeshlessModes {
  Eigen::VectorXd frequencies, eigenvalues, damping_ratios;
  Eigen::MatrixXd rest_positions, node_modes;  // n x 3, 3 n x k
  Eigen::MatrixXd samples, sample_modes;       // m x 3, 3 m x k
  int rigid_modes = 0;                         // left out of the above
};
MeshlessModes compute_meshless_modes(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);
bool gradcheck_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);
bool run_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);

}  // namespace tailor
