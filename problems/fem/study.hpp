#pragma once
// Study: an optimization problem written in C++ over what the scene layer already does. A study
// is a scene (read from a file, given as JSON, or built here with the scene format's selectors)
// plus what C++ adds to it: objective terms and energy terms of the program's own classes, a
// design map, constraints. It only composes the layers below it:
//
//   scene JSON --parse_scene--> Scene --build_inverse_problem(+ InverseExtensions)--> InverseProblem
//   InverseProblem::functional (StaticFunctional) --taylor_test / minimize--> report (run_inverse_problem)
//
//   Study study = Study::from_file("bar.json");
//   study.objective("compliance", [](const InverseProblem& p) { return make_compliance(p); }, 1e-3);
//   if (!study.taylor_test().passed()) return 1;
//   InverseRun run = study.run("out/bar", &std::cout);
//
// Everything JSON-shaped uses the scene format key for key (docs/scenes.md): mistakes are
// SceneErrors naming the key path, as for a scene file. The problem is built on first use
// (problem(), taylor_test(), run()); changing the study after that is a std::logic_error.
#include <functional>
#include <iosfwd>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_term_registry.hpp"

namespace tailor {

// The scene format's selectors as JSON values (docs/scenes.md, "Selectors").
namespace select {
nlohmann::json plane(const std::string& axis, double value);           // |coordinate - value| <= 1e-9 diag
nlohmann::json box(std::vector<double> min, std::vector<double> max);  // vertices inside (bounds included)
nlohmann::json list(std::vector<int> ids);                             // vertex ids
nlohmann::json boundary();                                             // every surface vertex
nlohmann::json all();                                                  // every element
nlohmann::json region(int region);                                     // elements of a mesh region
nlohmann::json element_box(std::vector<double> min, std::vector<double> max);  // centroid inside
}  // namespace select

// Makes a constraint once the problem exists (it may hold a functional of the problem's model).
using ConstraintFactory = std::function<Constraint(const InverseProblem& problem)>;
using ObjectiveFactory = std::function<ObjectivePtr(const InverseProblem& problem)>;

class Study {
 public:
  Study();  // an empty scene, to build below
  static Study from_file(const std::string& path);
  // `source` names the scene in messages; `directory` resolves the relative paths it holds.
  static Study from_json(nlohmann::json scene, const std::string& source = "(scene)",
                         const std::string& directory = "");

  // Building the scene (each appends to the scene's JSON; scene() has every other key).
  Study& mesh_box(std::vector<double> min, std::vector<double> max, std::vector<int> cells);
  Study& mesh_file(const std::string& path);
  Study& material(nlohmann::json elements, const std::string& model, double youngs_modulus,
                  double poisson_ratio, double density = 0.0);
  Study& fix(nlohmann::json vertices);  // clamp: zero displacement
  Study& prescribe(nlohmann::json vertices, std::vector<double> displacement);
  Study& traction(nlohmann::json faces, std::vector<double> traction);  // force per area
  Study& force(nlohmann::json vertices, std::vector<double> force);     // per selected vertex
  nlohmann::json& scene();

  // The design: the scene's "inverse.design" object, or a map z -> E per element of the
  // program's own (then granularity, map, min, max and initial do not apply).
  Study& design(nlohmann::json design);
  Study& design(ParameterizationPtr element_map, Vector z0, Bounds bounds = {});

  // Objective terms: one of the scene format's (or a registered type's), as JSON; or an
  // Objective of the program's own, made when the problem is built, added as weight * term.
  Study& objective(nlohmann::json term);
  Study& objective(const std::string& name, ObjectiveFactory make, double weight = 1.0);
  // Energy terms of the program's own, added to every model of the problem (at full strength).
  Study& energy(EnergyTermFactory make);

  // The scene's "inverse.optimizer" object (back-end, tolerances, ...); constraints for the
  // back-ends that take them (constraint functions below).
  Study& optimizer(nlohmann::json optimizer);
  Study& constraint(ConstraintFactory make);

  // Where the problem's Newton solves print one line per iteration while it is built (its
  // synthetic-observation solves); none by default. A caller that must stop a long build (the
  // Python module, on Ctrl-C) gives a stream that throws from its writes.
  Study& build_progress(std::ostream* progress);
  // The parsed scene and the built problem (built on first call).
  const Scene& parsed_scene();
  InverseProblem& problem();
  // Derivative checks of every energy term of the problem's model (tailor check).
  std::vector<EnergyTermCheck> check_energy_terms(unsigned seed = 1);
  // Taylor test of J at z0 (the scene's gradcheck settings unless given), with the forward
  // solves tightened to the round-off floor for it (as tailor gradcheck). Writes no file.
  TaylorTestResult taylor_test(std::optional<TaylorTestOptions> options = std::nullopt);
  // Minimizes from z0 with the scene's (or optimizer()'s) back-end and the constraints; writes
  // out_dir/report.json, result.vtu, convergence.png and youngs_modulus.png like `tailor run`.
  // The run owns the problem: a later call builds it afresh.
  InverseRun run(const std::string& out_dir, std::ostream* log = nullptr, std::ostream* progress = nullptr);

 private:
  void check_unbuilt(const char* what) const;
  nlohmann::json& inverse();
  nlohmann::json document_;
  std::string source_ = "(scene)", directory_;
  InverseExtensions extensions_;
  std::vector<ConstraintFactory> constraints_;
  std::optional<Scene> scene_;
  std::unique_ptr<InverseProblem> problem_;
  std::ostream* build_progress_ = nullptr;
};

// Reduced functionals for constraints (each has its own Taylor test in tests/study).
// The volume-weighted mean of E(z) over the elements: no solve, exact gradient.
std::shared_ptr<ReducedFunctional> mean_youngs_modulus(const InverseProblem& problem);
// objective(x*(z), p(z)) on the problem's model and design (make_static_functional).
std::shared_ptr<ReducedFunctional> state_functional(const InverseProblem& problem, ObjectivePtr objective);

// f(z) <= bound, f(z) >= bound, f(z) = bound, as c(z) = (f(z) - bound) / scale (sign flipped for
// at_least) with scale = |bound| (1 when bound = 0), so that constraint tolerances are relative.
Constraint at_most(std::shared_ptr<ReducedFunctional> f, double bound, std::string name);
Constraint at_least(std::shared_ptr<ReducedFunctional> f, double bound, std::string name);
Constraint equal_to(std::shared_ptr<ReducedFunctional> f, double bound, std::string name);

}  // namespace tailor
