#pragma once
// The verbs on a scene with a "dynamics" section (problems/fem/dynamic_scene.hpp), callable from
// C++: `tailor simulate` integrates it in time and writes the frames, the series and the
// report (problems/fem/dynamic_report.hpp); `tailor gradcheck` without an "inverse" section
// Taylor-tests the time-dependent adjoint of its trajectory objective.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "adjoint/transient_functional.hpp"
#include "problems/fem/dynamic_report.hpp"
#include "problems/fem/inverse_report.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

// Throws SceneError for scene problems (e.g. a material without a positive density) and
// std::runtime_error when an output cannot be written; a failed step is not an exception
// (see DynamicRun::completed).
DynamicRun simulate_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log);

// The design `tailor gradcheck` tests on a dynamic scene (and Python's functional()): per-element
// log Young's modulus, per-element log density and, with Rayleigh damping, alpha and beta, under
// the scene's trajectory objective, through the time-dependent adjoint over all its steps.
struct DynamicDesign {
  DynamicSceneModel scene_model;
  ParameterizationPtr parameterization;
  Vector z0;
  int steps = 0;                    // the trajectory's: states 0 ... steps
  std::vector<std::string> labels;  // "log_youngs_modulus[e]", "log_density[e]", "rayleigh_alpha", ...
  std::unique_ptr<TimeIntegrator> integrator;
  std::unique_ptr<TransientFunctional> functional;
};
// Throws SceneError when the dynamics section has no objective, and what build_dynamic_scene throws.
std::unique_ptr<DynamicDesign> build_dynamic_design(const Scene& scene);

// Taylor test of the time-dependent adjoint (TransientFunctional) of the scene's trajectory
// objective over all its steps, in per-element log Young's modulus, per-element log density and,
// with Rayleigh damping, alpha and beta; writes out_dir/gradcheck.json. Throws SceneError when
// the dynamics section has no objective.
GradcheckRun gradcheck_dynamic_scene(const Scene& scene, const std::string& out_dir, unsigned seed,
                                     std::ostream* log);

}  // namespace tailor
