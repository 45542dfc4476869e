#pragma once
// The work behind the CLI verbs, callable from C++ (the executable only parses arguments and
// maps outcomes to exit codes).
#include <iosfwd>
#include <string>

#include "problems/fem/report.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/static_scene.hpp"

namespace tailor {

struct SimulateRun {
  StaticSetup setup;
  StaticSolution solution;
  RunTimings timings;
  std::string report_path;  // out_dir/report.json
  std::string result_path;  // out_dir/result.vtu
};

// `tailor simulate`: sets the scene up, solves it, and writes out_dir/report.json and
// out_dir/result.vtu (creating out_dir), also when the solve fails. Newton iterations, a
// summary and timings go to `log` when set. Throws SceneError / MeshError for bad input and
// std::runtime_error when the outputs cannot be written; a failed solve is not an exception
// (see solution.converged).
SimulateRun simulate_scene(const Scene& scene, const std::string& out_dir, std::ostream* log = nullptr);

// Per-element material parameters that replace the scene's in one simulate run (the Python
// module's scene.simulate(youngs_modulus=..., poisson_ratio=...)); an empty vector keeps the
// scene's values. Young's moduli in the scene's stress unit, > 0; Poisson's ratios in (-1, 0.5).
struct MaterialOverrides {
  Eigen::VectorXd youngs_modulus;  // one per mesh element, or empty
  Eigen::VectorXd poisson_ratio;   // one per mesh element, or empty
  bool empty() const { return youngs_modulus.size() == 0 && poisson_ratio.size() == 0; }
};
// simulate_scene with the overrides applied to the setup before the solve (the report and
// result.vtu show them). Throws std::invalid_argument for an override of the wrong length, with
// a value out of range, or on elements of a spline material (whose energy has no E or nu).
SimulateRun simulate_scene(const Scene& scene, const MaterialOverrides& overrides, const std::string& out_dir,
                           std::ostream* log = nullptr);

// `tailor check`: derivative checks of every energy term of the scene's model (see
// check_static_scene); prints each table to `log` when set. Returns true when no check failed.
bool check_scene(const Scene& scene, unsigned seed, std::ostream* log);

}  // namespace tailor
