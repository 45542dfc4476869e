// The Study facade and its extension points, through public headers only (as a program outside
// the library would use them): C++-built scenes against scene files, a user Objective, a user
// EnergyTerm, a user Parameterization, a user scene term type, constraints on every back-end
// that takes them, and the files of `tailor run`.
#include "problems/fem/study.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "adjoint/derivative_check.hpp"
#include "adjoint/parameterization.hpp"
#include "forward/mesh/generate.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/json_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::study_test {
namespace {

namespace fs = std::filesystem;

std::string scene_file(const char* name) {
  return std::string(::tailor::testing::source_dir()) + "/scenes/" + name;
}

std::string scratch(const std::string& name) {
  const fs::path dir = fs::path(::tailor::testing::binary_dir()) / "tests" / "study" / name;
  fs::remove_all(dir);
  return dir.string();
}

// The bar of scenes/two_material_bar_inverse.json, written with the facade's builders.
Study two_material_bar() {
  Study study;
  study.scene()["name"] = "two_material_bar_inverse";
  study.mesh_box({0, 0, 0}, {4, 1, 1}, {8, 2, 2})
      .material(select::element_box({0, 0, 0}, {2, 1, 1}), "neo_hookean", 3e5, 0.3)
      .material(select::element_box({2, 0, 0}, {4, 1, 1}), "neo_hookean", 1e5, 0.3)
      .fix(select::plane("x", 0))
      .traction(select::plane("x", 4), {200, 0, -50})
      .design({{"parameter", "youngs_modulus"}, {"granularity", "per_material"}, {"min", 1e3}, {"max", 1e8}})
      .objective({{"type", "synthetic_observations"},
                  {"vertices", select::plane("z", 1)},
                  {"youngs_modulus", {{"materials", {1e5, 3e5}}}}})
      .optimizer({{"backend", "nlopt_lbfgs"}, {"max_iterations", 100}});
  return study;
}

// A small linear cantilever (24 tets), one variable per element, z = log E.
Study small_cantilever(const char* backend = "nlopt_lbfgs") {
  Study study;
  study.mesh_box({0, 0, 0}, {4, 1, 1}, {4, 1, 1})
      .material(select::all(), "linear", 1e5, 0.3)
      .fix(select::plane("x", 0))
      .traction(select::plane("x", 4), {0, 0, -1e2})
      .design({{"parameter", "youngs_modulus"}, {"granularity", "per_element"}, {"min", 1e4}, {"max", 1e6}})
      .optimizer({{"backend", backend}, {"max_iterations", 300}, {"gradient_tolerance", 1e-7}});
  return study;
}

// J(x, p) = f . (x - X) + a/2 sum_e (E_e / E_ref)^2: compliance plus a penalty on E, so that
// both partial derivatives are exercised. `gradient_error` scales dJ/dx (1: exact).
class PenalizedCompliance final : public Objective {
 public:
  PenalizedCompliance(Vector forces, Vector rest, int offset, int count, double a, double reference,
                      double gradient_error = 1.0)
      : f_(std::move(forces)),
        rest_(std::move(rest)),
        offset_(offset),
        n_(count),
        a_(a),
        ref_(reference),
        error_(gradient_error) {}
  std::string name() const override { return "penalized_compliance"; }
  double value(const Vector& x, const Vector& p) const override {
    return f_.dot(x - rest_) + 0.5 * a_ * (p.segment(offset_, n_) / ref_).squaredNorm();
  }
  void add_gradient_x(const Vector&, const Vector&, Vector& gx) const override { gx += error_ * f_; }
  void add_gradient_p(const Vector&, const Vector& p, Vector& gp) const override {
    gp.segment(offset_, n_) += a_ * p.segment(offset_, n_) / (ref_ * ref_);
  }
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector&, const Vector&, const Vector&, const Vector& dp, Vector&,
                         Vector& out_p) const override {
    out_p.segment(offset_, n_) += a_ * dp.segment(offset_, n_) / (ref_ * ref_);
  }

 private:
  Vector f_, rest_;
  int offset_, n_;
  double a_, ref_, error_;
};

ObjectiveFactory penalized_compliance(double gradient_error = 1.0) {
  return [gradient_error](const InverseProblem& p) {
    const StaticSolution start = solve_static(p.setup);
    const double c0 = p.setup.nodal_forces.dot(start.positions - p.setup.rest_state());
    return std::make_shared<PenalizedCompliance>(p.setup.nodal_forces / c0, p.setup.rest_state(),
                                                 p.youngs_offset, p.setup.mesh.num_elements(), 1e-2, 1e5,
                                                 gradient_error);
  };
}

// Nonlinear springs from anchors a distance h below the selected vertices (as in
// examples/custom_energy.cpp). `hessian_error` scales the Hessian (1: exact).
class Springs final : public EnergyTerm {
 public:
  Springs(std::vector<int> vertices, const Vector& rest, double k, double h, double hessian_error = 1.0)
      : vertices_(std::move(vertices)), k_(k), h_(h), error_(hessian_error) {
    for (int v : vertices_) anchors_.push_back(rest.segment<3>(3 * v) - Eigen::Vector3d(0, 0, h_));
  }
  std::string name() const override { return "springs"; }
  void hessian_pattern(HessianPattern& pattern) const override {
    for (int v : vertices_)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) pattern.push_back({3 * v + i, 3 * v + j});
  }
  void evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const override {
    for (std::size_t s = 0; s < vertices_.size(); ++s) {
      const int v = vertices_[s];
      const Eigen::Vector3d d = x.segment<3>(3 * v) - anchors_[s];
      const double r = d.norm();
      const Eigen::Vector3d n = d / r;
      if (request.value) *request.value += 0.5 * k_ * (r - h_) * (r - h_);
      if (request.gradient) request.gradient->segment<3>(3 * v) += k_ * (r - h_) * n;
      if (request.hessian_values) {
        double lateral = 1.0 - h_ / r;
        if (request.hessian_mode == HessianMode::projected) lateral = std::max(lateral, 0.0);
        const Eigen::Matrix3d H =
            error_ * k_ * (n * n.transpose() + lateral * (Eigen::Matrix3d::Identity() - n * n.transpose()));
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(request.hessian_values + 9 * s) = H;
      }
    }
  }

 private:
  std::vector<int> vertices_;
  std::vector<Eigen::Vector3d> anchors_;
  double k_, h_, error_;
};

std::vector<int> vertices_at_z(const Mesh& mesh, double z) {
  std::vector<int> out;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.rest_positions(v, 2) == z) out.push_back(v);
  return out;
}

// E_e = s z0 (1 + z1 c_e), c_e the x coordinate of element e's centroid, s a fixed scale: a map
// of two variables of order one, bilinear in z.
class LinearGradientMap final : public Parameterization {
 public:
  LinearGradientMap(const Mesh& mesh, double scale) : c_(mesh.num_elements()), s_(scale) {
    for (int e = 0; e < mesh.num_elements(); ++e) c_[e] = mesh.rest_positions(mesh.elements.row(e), 0).mean();
  }
  std::string name() const override { return "linear_gradient"; }
  int num_design() const override { return 2; }
  int num_params() const override { return static_cast<int>(c_.size()); }
  Vector apply(const Vector& z) const override { return s_ * z[0] * (1.0 + z[1] * c_.array()).matrix(); }
  Vector jacobian_times(const Vector& z, const Vector& dz) const override {
    return s_ * (dz[0] * (1.0 + z[1] * c_.array()) + z[0] * dz[1] * c_.array()).matrix();
  }
  Vector jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    return s_ * Eigen::Vector2d(w.dot((1.0 + z[1] * c_.array()).matrix()), z[0] * w.dot(c_));
  }
  Vector second_derivative_times(const Vector&, const Vector& w, const Vector& dz) const override {
    // d2E_e/dz0dz1 = s c_e: sum_e w_e (H_e dz) = s (dz1 w.c, dz0 w.c).
    return s_ * Eigen::Vector2d(dz[1] * w.dot(c_), dz[0] * w.dot(c_));
  }

 private:
  Vector c_;
  double s_;
};

void expect_first_then_second_order(const TaylorTestResult& taylor) {
  EXPECT_TRUE(taylor.passed()) << taylor.message << "\n" << taylor.table();
  EXPECT_GE(taylor.rate1, 1.9) << taylor.table();
  EXPECT_NEAR(taylor.rate0, 1.0, 0.1) << taylor.table();  // the first-order regime the rate is judged in
}

TEST(Study, CppBuiltSceneMatchesTheSceneFile) {
  // Reference: the scene file through the lower layers (read_scene, build_inverse_problem).
  const std::unique_ptr<InverseProblem> reference =
      build_inverse_problem(read_scene(scene_file("two_material_bar_inverse.json")));
  const double expected = reference->functional->value(reference->z0);
  Study built = two_material_bar();
  Study loaded = Study::from_file(scene_file("two_material_bar_inverse.json"));
  for (Study* study : {&built, &loaded}) {
    InverseProblem& p = study->problem();
    ASSERT_EQ(p.z0.size(), 2);
    EXPECT_EQ(p.z0, reference->z0);
    EXPECT_EQ(p.bounds.lower, reference->bounds.lower);
    EXPECT_NEAR(p.functional->value(p.z0), expected, 1e-12 * std::abs(expected));
  }
}

TEST(Study, UserObjectiveDerivativesAndTaylorTest) {
  Study study = small_cantilever();
  study.objective("penalized_compliance", penalized_compliance());
  InverseProblem& p = study.problem();
  const Objective& J = *p.terms.back().term;
  ASSERT_EQ(p.terms.back().type, "penalized_compliance");
  // Partial derivatives against central differences (reference: J's values), at a perturbed state.
  const Vector x = p.setup.rest_state() + 1e-2 * Vector::Random(p.setup.num_dofs());
  const Vector params = p.parameterization->apply(p.z0);
  const Vector dx = Vector::Random(x.size()), dp = params.cwiseProduct(Vector::Random(params.size()));
  Vector gx = Vector::Zero(x.size()), gp = Vector::Zero(params.size());
  J.add_gradient_x(x, params, gx);
  J.add_gradient_p(x, params, gp);
  const auto along = [&](double t) { return Vector::Constant(1, J.value(x + t * dx, params + t * dp)); };
  EXPECT_TRUE(
      check_directional_derivative("gradient", along, Vector::Constant(1, gx.dot(dx) + gp.dot(dp)), {})
          .passed);
  Vector hx = Vector::Zero(x.size()), hp = Vector::Zero(params.size());
  J.add_hessian_times(x, params, dx, dp, hx, hp);
  const auto gradient_p_along = [&](double t) {
    Vector g = Vector::Zero(params.size());
    J.add_gradient_p(x + t * dx, params + t * dp, g);
    return g;
  };
  EXPECT_TRUE(check_directional_derivative("hessian_p", gradient_p_along, hp, {}).passed);
  expect_first_then_second_order(study.taylor_test());
}

TEST(Study, WrongUserGradientFailsTheTaylorTest) {
  // The same objective with dJ/dx scaled by 1.5: the adjoint gradient is wrong, the test says so.
  Study study = small_cantilever();
  study.objective("penalized_compliance", penalized_compliance(1.5));
  const TaylorTestResult taylor = study.taylor_test();
  EXPECT_FALSE(taylor.passed()) << taylor.table();
}

TEST(Study, UserEnergyTermPassesTheDerivativeCheckAndJoinsEveryModel) {
  Study study = small_cantilever();
  study.design(
      {{"parameter", "youngs_modulus"}, {"granularity", "per_material"}, {"min", 1e4}, {"max", 1e6}});
  study.objective(
      {{"type", "synthetic_observations"}, {"vertices", select::boundary()}, {"youngs_modulus", 2e5}});
  study.energy([](const StaticSetup& s) {
    return std::make_unique<Springs>(vertices_at_z(s.mesh, 0.0), s.rest_state(), 1e3, 0.5);
  });
  const std::vector<EnergyTermCheck> checks = study.check_energy_terms();
  bool found = false;
  for (const EnergyTermCheck& c : checks) {
    EXPECT_FALSE(check_failed(c)) << c.table();
    found = found || c.term == "springs";
  }
  EXPECT_TRUE(found);
  InverseProblem& p = study.problem();
  // A wrong Hessian fails the same check (reference: the term's own gradient).
  const Springs wrong(vertices_at_z(p.setup.mesh, 0.0), p.setup.rest_state(), 1e3, 0.5, 1.2);
  const Vector x = p.setup.rest_state() + 1e-2 * Vector::Random(p.setup.num_dofs());
  EXPECT_FALSE(check_energy_term(wrong, x, p.setup.parameters()).passed());
  // The springs carry load: the equilibrium differs from the one without them.
  StaticSetup without = p.setup;
  without.extra_terms.clear();
  const double sag = solve_static(without).max_displacement,
               supported = solve_static(p.setup).max_displacement;
  EXPECT_LT(supported, 0.9 * sag);
  expect_first_then_second_order(study.taylor_test());
  // Observations simulated with the springs are fitted with the springs: E comes back.
  const InverseRun run = study.run(scratch("springs"));
  EXPECT_NEAR(run.design_values[0] / 2e5, 1.0, 1e-6);
}

TEST(Study, UserParameterizationDesignsTheField) {
  const Mesh mesh =
      box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), 4, 1, 1);  // small_cantilever's
  Study designed = small_cantilever();
  // Observations of E = 1e5 (1 + 0.25 x), the map's own family: z = (1, 0.25) fits exactly.
  designed.objective({{"type", "synthetic_observations"},
                      {"vertices", select::boundary()},
                      {"youngs_modulus", {{"value", 1e5}, {"gradient", {0.25, 0, 0}}}}});
  auto map = std::make_shared<LinearGradientMap>(mesh, 1e5);
  // The map's Jacobian products against central differences of apply (reference).
  const Vector z = Eigen::Vector2d(2, 0.1), dz = Eigen::Vector2d(0.1, 0.05),
               w = Vector::Random(mesh.num_elements());
  EXPECT_TRUE(check_directional_derivative("jacobian", [&](double t) { return map->apply(z + t * dz); },
                                           map->jacobian_times(z, dz), {})
                  .passed);
  EXPECT_NEAR(w.dot(map->jacobian_times(z, dz)), map->jacobian_transpose_times(z, w).dot(dz), 1e-9 * 2e5);
  designed.design(map, Eigen::Vector2d(2, 0.0));
  ASSERT_EQ(designed.problem().setup.mesh.num_elements(), mesh.num_elements());
  expect_first_then_second_order(designed.taylor_test());
  const InverseRun run = designed.run(scratch("parameterization"));
  EXPECT_NEAR(run.result.z[0], 1.0, 1e-5);
  EXPECT_NEAR(run.result.z[1], 0.25, 1e-5);
  std::ifstream in(run.report_path);
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["design"]["granularity"], "element_map");
  EXPECT_EQ(report["design"]["map"], "linear_gradient");
}

// 1/2 (mean z-displacement of the selected vertices - target)^2: a registered scene term type.
class MeanSag final : public Objective {
 public:
  MeanSag(std::vector<int> vertices, Vector rest, double target)
      : v_(std::move(vertices)), rest_(std::move(rest)), t_(target) {}
  std::string name() const override { return "mean_sag"; }
  double mean(const Vector& x) const {
    double m = 0.0;
    for (int v : v_) m += x[3 * v + 2] - rest_[3 * v + 2];
    return m / static_cast<double>(v_.size());
  }
  double value(const Vector& x, const Vector&) const override { return 0.5 * std::pow(mean(x) - t_, 2); }
  void add_gradient_x(const Vector& x, const Vector&, Vector& gx) const override {
    for (int v : v_) gx[3 * v + 2] += (mean(x) - t_) / static_cast<double>(v_.size());
  }
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector&, const Vector&, const Vector& dx, const Vector&, Vector& out_x,
                         Vector&) const override {
    double m = 0.0;
    for (int v : v_) m += dx[3 * v + 2];
    const double n = static_cast<double>(v_.size());
    for (int v : v_) out_x[3 * v + 2] += m / (n * n);
  }

 private:
  std::vector<int> v_;
  Vector rest_;
  double t_;
};

void register_mean_sag() {
  static const bool registered = [] {
    register_objective_term(
        {"test_mean_sag", true, {"vertices", "target"}, {"vertices"}, [](const ObjectiveTermContext& c) {
           const double target = c.node.has("target") ? c.node.at("target").number() : 0.0;
           return std::make_shared<MeanSag>(c.vertices("vertices"), c.problem.setup.rest_state(), target);
         }});
    return true;
  }();
  (void)registered;
}

nlohmann::json sag_scene(nlohmann::json term) {
  return {{"mesh", {{"box", {{"min", {0, 0, 0}}, {"max", {4, 1, 1}}, {"cells", {4, 1, 1}}}}}},
          {"materials",
           {{{"elements", "all"}, {"model", "linear"}, {"youngs_modulus", 1e5}, {"poisson_ratio", 0.3}}}},
          {"dirichlet", {{{"vertices", select::plane("x", 0)}}}},
          {"loads", {{"tractions", {{{"faces", select::plane("x", 4)}, {"traction", {0, 0, -1e2}}}}}}},
          {"inverse",
           {{"design",
             {{"parameter", "youngs_modulus"}, {"granularity", "per_material"}, {"min", 1e3}, {"max", 1e8}}},
            {"objective", {std::move(term)}}}}};
}

TEST(Study, RegisteredSceneTermTypeIsNamedByScenes) {
  register_mean_sag();
  // Scenes name it like tailor's own types, through read_scene and through the facade.
  const fs::path file = fs::path(scratch("registered")) / "sag.json";
  fs::create_directories(file.parent_path());
  // The weight scales J (1/2 (m - t)^2, m ~ 1e-2) to order 1 for the optimizer's absolute tolerances.
  std::ofstream(file) << sag_scene(
      {{"type", "test_mean_sag"}, {"vertices", select::plane("x", 4)}, {"target", -0.01}, {"weight", 1e4}});
  const std::unique_ptr<InverseProblem> problem = build_inverse_problem(read_scene(file.string()));
  ASSERT_EQ(problem->terms.size(), 1u);
  EXPECT_EQ(problem->terms[0].type, "test_mean_sag");
  EXPECT_EQ(problem->terms[0].key, "inverse.objective[0]");
  EXPECT_EQ(problem->terms[0].coefficient, 1e4);  // the weight, not normalized
  Study study = Study::from_file(file.string());
  expect_first_then_second_order(study.taylor_test());
  const InverseRun run = study.run(scratch("registered_run"));
  ASSERT_TRUE(run.solution.converged) << run.result.report();
  EXPECT_NEAR(dynamic_cast<const MeanSag&>(*run.problem->terms[0].term).mean(run.solution.positions), -0.01,
              1e-8);

  // Its keys are checked like tailor's: unknown ones and missing required ones name the key path.
  try {
    Study::from_json(sag_scene({{"type", "test_mean_sag"}, {"vertices", select::boundary()}, {"bogus", 1}}),
                     "s.json")
        .problem();
    ADD_FAILURE() << "an unknown key was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: inverse.objective[0].bogus: unknown key"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Study::from_json(sag_scene({{"type", "test_mean_sag"}})).problem(), SceneError);
  // The list of types in the message of an unknown type includes it.
  try {
    Study::from_json(sag_scene({{"type", "no_such_term"}})).problem();
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("test_mean_sag"), std::string::npos) << e.what();
  }
  const auto build = [](const ObjectiveTermContext&) -> ObjectivePtr { return nullptr; };
  EXPECT_THROW(register_objective_term({"test_mean_sag", true, {}, {}, build}), std::logic_error);
  EXPECT_THROW(register_objective_term({"observations", true, {}, {}, build}), std::logic_error);
  EXPECT_THROW(register_objective_term({"test_other", true, {}, {"missing"}, build}), std::logic_error);
}

TEST(Study, ConstraintFunctionalsPassTheirTaylorTests) {
  Study study = small_cantilever();
  study.objective("penalized_compliance", penalized_compliance());
  InverseProblem& p = study.problem();
  // z = log E per element: the mean is nonlinear in z (a linear one would be round_off).
  const Vector z = p.z0 + 0.3 * Vector::Random(p.z0.size());
  expect_first_then_second_order(taylor_test(*mean_youngs_modulus(p), z));
  // Reference for its value: the volume-weighted mean computed here.
  const Eigen::VectorXd volumes = element_volumes(p.setup.mesh).cwiseAbs();
  EXPECT_NEAR(mean_youngs_modulus(p)->value(z), volumes.dot(p.youngs_modulus(z)) / volumes.sum(), 1e-9 * 1e5);
  const std::shared_ptr<ReducedFunctional> compliance = state_functional(p, p.terms.back().term);
  expect_first_then_second_order(taylor_test(*compliance, z));
  // The constraints made of them: c = -(f - bound) / bound for at_least; its gradient against
  // central differences of its value (reference), and its value against f's.
  const Constraint c = at_least(compliance, 0.5, "compliance");
  const Vector dz = Vector::Random(z.size());
  Vector gradient;
  const double value = c.evaluate(z, &gradient);
  EXPECT_NEAR(value, -(compliance->value(z) - 0.5) / 0.5, 1e-12);
  const auto along = [&](double t) { return Vector::Constant(1, c.evaluate(z + t * dz, nullptr)); };
  EXPECT_TRUE(
      check_directional_derivative("constraint", along, Vector::Constant(1, gradient.dot(dz)), {}).passed);
}

TEST(Study, MaterialModesDesign) {
  // granularity "modes" through the facade: 4 Laplacian modes of the 24-tet field.
  Study study = small_cantilever();
  study
      .design({{"parameter", "youngs_modulus"},
               {"granularity", "modes"},
               {"modes", 4},
               {"min", 1e4},
               {"max", 1e6}})
      .objective(
          {{"type", "synthetic_observations"}, {"vertices", select::boundary()}, {"youngs_modulus", 2e5}});
  ASSERT_EQ(study.problem().num_design(), 4);
  ASSERT_TRUE(study.problem().modal.has_value());
  expect_first_then_second_order(study.taylor_test());
}

TEST(Study, ConstrainedDesignOnEveryConstrainedBackend) {
  const double budget = 1e5;
  for (const char* backend : {"ipopt", "nlopt_slsqp", "nlopt_mma"}) {
    SCOPED_TRACE(backend);
    Study study = small_cantilever(backend);
    study.objective("penalized_compliance", penalized_compliance())
        .constraint(
            [budget](const InverseProblem& p) { return at_most(mean_youngs_modulus(p), budget, "mean E"); });
    const InverseRun run = study.run(scratch(std::string("constrained_") + backend));
    const double mean = mean_youngs_modulus(*run.problem)->value(run.result.z);
    EXPECT_LE(mean, budget * (1 + 1e-5));
    // Reference: the uniform design (J = 1 + penalty at z0) that meets the budget exactly.
    EXPECT_LT(run.result.objective, 0.95 * run.result.history.front().objective) << run.result.report();
    EXPECT_GT(mean, 0.99 * budget);  // the budget is worth using: the constraint is active
  }
  // An equality (ipopt and slsqp take them): the mean lands on the value.
  for (const char* backend : {"ipopt", "nlopt_slsqp"}) {
    SCOPED_TRACE(backend);
    Study study = small_cantilever(backend);
    study.objective("penalized_compliance", penalized_compliance()).constraint([](const InverseProblem& p) {
      return equal_to(mean_youngs_modulus(p), 8e4, "mean E");
    });
    const InverseRun run = study.run(scratch(std::string("equality_") + backend));
    EXPECT_NEAR(mean_youngs_modulus(*run.problem)->value(run.result.z) / 8e4, 1.0, 1e-5);
  }
}

TEST(Study, RunWritesWhatTailorRunWrites) {
  // Reference: run_inverse_scene (the body of `tailor run`) on the same scene file.
  const std::string file = scene_file("two_material_bar_inverse.json");
  const InverseRun reference = run_inverse_scene(read_scene(file), scratch("reference"));
  Study study = Study::from_file(file);
  std::ostringstream log;
  const std::string out = scratch("study_run");
  const InverseRun run = study.run(out, &log);
  for (const char* name : {"report.json", "result.vtu", "convergence.png", "youngs_modulus.png"})
    EXPECT_TRUE(fs::exists(fs::path(out) / name)) << name;
  ASSERT_EQ(run.result.z.size(), reference.result.z.size());
  for (Eigen::Index k = 0; k < run.result.z.size(); ++k)
    EXPECT_NEAR(run.result.z[k], reference.result.z[k], 1e-9 * std::abs(reference.result.z[k]));
  EXPECT_NE(log.str().find("wrote " + run.report_path), std::string::npos) << log.str();
}

TEST(Study, EveryBackendRecoversTheBar) {
  // Reference: the true moduli (1e5, 3e5) the observations were simulated with, from 3x off.
  // Plain descent converges linearly on this ill-conditioned pair: it is only asked to lower J by
  // 100x in 300 iterations (tests/validation runs it to 1e-6 in 3000).
  for (OptimizerBackend backend :
       {OptimizerBackend::ipopt, OptimizerBackend::nlopt_lbfgs, OptimizerBackend::nlopt_mma,
        OptimizerBackend::nlopt_slsqp, OptimizerBackend::ceres_lbfgs, OptimizerBackend::ceres_least_squares,
        OptimizerBackend::gradient_descent}) {
    SCOPED_TRACE(to_string(backend));
    const bool descent = backend == OptimizerBackend::gradient_descent;
    Study study = two_material_bar();
    if (backend == OptimizerBackend::ceres_lbfgs)  // takes no bounds
      study.design({{"parameter", "youngs_modulus"}, {"granularity", "per_material"}});
    study.optimizer({{"backend", to_string(backend)},
                     {"max_iterations", descent ? 300 : 500},
                     {"gradient_tolerance", 1e-13}});
    const InverseRun run = study.run(scratch("backend_" + to_string(backend)));
    if (descent) {
      EXPECT_LT(run.result.objective, 1e-2 * run.result.history.front().objective) << run.result.report();
      continue;
    }
    EXPECT_NEAR(run.design_values[0] / 1e5, 1.0, 1e-6) << run.result.report();
    EXPECT_NEAR(run.design_values[1] / 3e5, 1.0, 1e-6) << run.result.report();
  }
}

TEST(Study, MistakesAreNamed) {
  Study study = two_material_bar();
  study.problem();
  EXPECT_THROW(study.objective({{"type", "tikhonov"}, {"prior", 1e5}}), std::logic_error);
  Study bad = two_material_bar();
  bad.design({{"parameter", "youngs_modulus"}, {"granularity", "per_thing"}});
  try {
    bad.problem();
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("inverse.design.granularity"), std::string::npos) << e.what();
  }
  Study wrong_map = two_material_bar();
  wrong_map.design(identity_map(3), Vector::Constant(3, 1e5));
  EXPECT_THROW(wrong_map.problem(), std::invalid_argument);  // 3 values for 192 elements
  // Without any data term, neither from the scene nor from C++: the scene's own message.
  Study empty = small_cantilever();
  EXPECT_THROW(empty.problem(), SceneError);
}

}  // namespace
}  // namespace tailor::study_test
