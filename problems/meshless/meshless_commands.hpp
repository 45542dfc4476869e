#pragma once
// The verbs of the `meshless` scene kind (docs/meshless.md, "Scenes"), each writing into
// out_dir: simulate (static equilibrium: report.json, nodes.vtu, samples.vtu), modes (modal
// analysis with Rayleigh damping ratios, modes.vtu, and warped modal dynamics under the scene's
// modes.force: frames/*.vtu and result.pvd), gradcheck (Taylor test of the inverse section's
// design functional: gradcheck.json) and run (the optimizer: report.json, samples.vtu at the
// best design).
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
bool gradcheck_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);
bool run_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);

}  // namespace tailor
