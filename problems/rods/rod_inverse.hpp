#pragma once
// Inverse design of rods: the "inverse" section of a rod scene (docs/rods.md, "Inverse design
// scenes") for `tailor gradcheck` and `tailor run`. The design is one or more per-edge or
// per-vertex parameter blocks of one rod (rest curvatures, rest twists, rest lengths, radii,
// Young's moduli), the objective a target shape (by default the rod's own drawn points: the rest
// shape that, under the scene's loads and supports, settles into the drawn one), through the
// static adjoint (adjoint/static_functional.hpp) with the exact Hessian.
#include <iosfwd>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/rods/rod_inverse_statics.hpp"
#include "problems/rods/rod_scene.hpp"

namespace tailor {

// A designed parameter block of the rod.
enum class RodDesignBlock { rest_curvature, rest_twist, rest_length, radius, youngs_modulus };
std::string to_string(RodDesignBlock block);

// How `tailor run` designs (the scene key inverse.method): inverse statics where it applies,
// falling back to the optimizer when its result is not a stable equilibrium at round-off
// (automatic, "auto"); inverse statics only (a scene where it does not apply is refused); the
// optimizer only (problems/rods/rod_inverse_statics.hpp, docs/rods.md).
enum class RodInverseMethod { automatic, inverse_statics, optimizer };
std::string to_string(RodInverseMethod method);

struct RodInverseSpec {
  int rod = 0;  // index into the scene's rods
  std::vector<RodDesignBlock> design;
  bool per_rod = false;  // radius / youngs_modulus / rest_length: one variable for the whole rod
  // Target positions of the rod's vertices (local indices), one row each.
  std::vector<int> target_vertices;
  Matrix target_positions;
  std::vector<int> components = {0, 1, 2};  // the coordinates that are matched
  double regularization = 0.0;              // Tikhonov weight on the designed blocks (docs/rods.md)
  RodInverseMethod method = RodInverseMethod::automatic;
  OptimizerOptions optimizer;
  unsigned seed = 1;  // of the gradcheck's random direction
};

struct RodInverseProblem {
  std::string name, source;
  RodSceneSpec scene;
  RodInverseSpec spec;
  RodSceneModel model;
  double length = 0.0;  // the designed rod's drawn length: the shape error's unit
  ParameterizationPtr parameterization;
  ObjectivePtr objective;
  std::unique_ptr<StaticFunctional> functional;
  Vector z0;
  std::vector<std::string> labels;  // per design variable: "rest_curvature[i][a]", "radius[j]", ...

  // Largest distance of a target vertex from its target at the equilibrium x (in the matched
  // components), over `length`.
  double shape_error(const Vector& x) const;
};

// The "inverse" section of a rod scene's document, `scene` its parsed rods. Throws SceneError
// naming the source and key path (unknown keys included).
RodInverseSpec parse_rod_inverse(const SceneNode& root, const RodSceneSpec& scene);

// Offset and size in p of a designed block of rod `rod`.
std::pair<int, int> rod_design_block_range(const RodSceneModel& model, int rod, RodDesignBlock block);

// The scene's document with its "inverse" section; `name` is the scene's name in the outputs.
// Throws SceneError naming the source and key path (unknown keys included).
std::unique_ptr<RodInverseProblem> build_rod_inverse(const SceneNode& root, const std::string& name);
// The same for a document without a file (tests, programs that build scenes in memory).
std::unique_ptr<RodInverseProblem> build_rod_inverse(const nlohmann::json& document,
                                                     const std::string& source, const std::string& name);

// `tailor gradcheck`: the Taylor test of J at z0 (of the Hessian-vector products too when
// `hessian`); prints the table to `log` and writes out_dir/gradcheck.json.
struct RodGradcheck {
  TaylorTestResult gradient;
  std::optional<TaylorTestResult> hessian;
  bool passed() const { return gradient.passed() && (!hessian || hessian->passed()); }
};
RodGradcheck gradcheck_rod_scene(const RodInverseProblem& problem, const std::string& out_dir,
                                 std::optional<unsigned> seed, bool hessian, std::ostream* log);

// `tailor run`: minimizes J from z0; writes out_dir/report.json and out_dir/rods.vtu at the best
// design (and rods_initial.vtu at z0).
struct RodInverseRun {
  // The design: z, status and message; by inverse statics without history or evaluations.
  OptimizerResult result;
  RodInverseMethod method = RodInverseMethod::optimizer;  // the one that gave the result
  std::optional<RodInverseStaticsResult> statics;        // when inverse statics ran
  std::string fallback;  // why the optimizer ran under "auto" (empty when it did not, or was asked)
  RodStability final_stability;  // of the equilibrium at the best design
  double initial_shape_error = 0.0, shape_error = 0.0;  // relative to the rod's length
  bool final_converged = false;                         // the equilibrium at the best design
  std::string report_path;
};
RodInverseRun run_rod_inverse(RodInverseProblem& problem, const std::string& out_dir, std::ostream* log,
                              std::ostream* progress);

}  // namespace tailor
