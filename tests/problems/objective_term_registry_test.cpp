// Every registered objective term type (problems/fem/objective_term_registry.hpp), through the
// example its entry carries: the scene with it parses, the inverse problem builds, and the
// reduced functional of the term alone passes its Taylor test -- first-order remainders falling
// at rate 1 (the asymptotic regime), then the second-order ones at rate >= 1.9. A type with
// second derivatives passes the same test one order up for its Hessian-vector products. A new
// type is tested here by being registered.
#include "problems/fem/objective_term_registry.hpp"

#include <gtest/gtest.h>

#include "adjoint/taylor_test.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/study.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::objective_term_registry_test {
namespace {

using nlohmann::json;

// The scene of ObjectiveTermType::example: a 4 x 1 x 1 linear bar clamped at x = 0, pulled down
// at x = 4 (tip deflection about 0.026 by beam theory), one log-E design variable per element.
// A regularization's example is paired with a data term (a scene needs one).
json test_scene(const json& term) {
  json objective = json::array({term});
  if (!find_objective_term_type(term.at("type"))->is_data)
    objective.push_back({{"type", "target_displacements"},
                         {"vertices", {{"plane", {{"axis", "x"}, {"value", 4}}}}},
                         {"displacement", {0.0, 0.0, -0.02}}});
  return {{"mesh", {{"box", {{"min", {0, 0, 0}}, {"max", {4, 1, 1}}, {"cells", {4, 1, 1}}}}}},
          {"materials",
           {{{"elements", "all"}, {"model", "linear"}, {"youngs_modulus", 1e5}, {"poisson_ratio", 0.3}}}},
          {"dirichlet", {{{"vertices", {{"plane", {{"axis", "x"}, {"value", 0}}}}}}}},
          {"loads",
           {{"tractions", {{{"faces", {{"plane", {{"axis", "x"}, {"value", 4}}}}}, {"traction", {0, 0, -10}}}}}}},
          {"inverse",
           {{"design", {{"parameter", "youngs_modulus"}, {"granularity", "per_element"}, {"map", "log"}}},
            {"objective", objective}}}};
}

void expect_first_then_second_order(const TaylorTestResult& taylor, const std::string& what) {
  EXPECT_TRUE(taylor.passed()) << what << ": " << taylor.message << "\n" << taylor.table();
  EXPECT_GE(taylor.rate1, 1.9) << what << "\n" << taylor.table();
  EXPECT_NEAR(taylor.rate0, 1.0, 0.1) << what << "\n" << taylor.table();
}

TEST(ObjectiveTermRegistry, ListsTailorsOwnTypes) {
  const std::vector<std::string> types = objective_term_types();
  for (const char* type :
       {"target_displacements", "observations", "synthetic_observations", "smoothness", "tikhonov", "handles"})
    EXPECT_NE(std::find(types.begin(), types.end(), type), types.end()) << type;
  // Each entry's keys are what its scenes may hold: required ones among them, an example given.
  for (const std::string& type : types) {
    const auto entry = find_objective_term_type(type);
    ASSERT_TRUE(entry);
    EXPECT_TRUE(entry->build) << type;
    EXPECT_TRUE(entry->example.is_object()) << type << " has no example for this test";
  }
  EXPECT_FALSE(find_objective_term_type("no_such_term"));
}

TEST(ObjectiveTermRegistry, EveryTypePassesItsTaylorTest) {
  for (const std::string& type : objective_term_types()) {
    SCOPED_TRACE(type);
    const auto entry = find_objective_term_type(type);
    ASSERT_TRUE(entry->example.is_object());
    Study study = Study::from_json(test_scene(entry->example), type + ".json",
                                   std::string(testing::test_data_dir()) + "/objective_terms");
    InverseProblem& problem = study.problem();
    ASSERT_EQ(problem.terms.front().type, type);
    // Away from the uniform start, where regularizations and their gradients vanish.
    Vector z = problem.z0;
    z.head(problem.num_material_design()) += 0.3 * Vector::Random(problem.num_material_design());
    const ObjectivePtr term = problem.terms.front().term;
    const auto functional = make_static_functional(problem, term);
    expect_first_then_second_order(taylor_test(*functional, z), type + " (gradient)");
    if (term->has_second_derivatives()) {
      // A gradient linear in z (smoothness of log E in z = log E) leaves remainders at round-off:
      // the product is exact then, while a wrong one would leave remainders of order h.
      const TaylorTestResult hessian = taylor_test_hessian(*functional, z);
      EXPECT_TRUE(hessian.passed() || hessian.status == TaylorStatus::round_off) << type << " (Hessian-vector product): " << hessian.message << "\n"
                                    << hessian.table();
    }
  }
}

TEST(ObjectiveTermRegistry, KeysAreCheckedFromTheEntry) {
  // The entry's key list is the whole check: a misspelled key of a built-in type names its path.
  json term = find_objective_term_type("tikhonov")->example;
  term["prio"] = 1.0;
  try {
    Study::from_json(test_scene(term), "keys.json").problem();
    ADD_FAILURE() << "a misspelled key was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("keys.json: inverse.objective[0].prio: unknown key"), std::string::npos)
        << e.what();
  }
  term.erase("prio");
  term.erase("prior");  // required
  EXPECT_THROW(Study::from_json(test_scene(term), "keys.json").problem(), SceneError);
}

TEST(ObjectiveTermRegistry, RefusesTakenNamesAndIncompleteEntries) {
  const auto build = [](const ObjectiveTermContext&) -> ObjectivePtr { return nullptr; };
  EXPECT_THROW(register_objective_term({"smoothness", false, {}, {}, build}), std::logic_error);
  EXPECT_THROW(register_objective_term({"", false, {}, {}, build}), std::logic_error);
  EXPECT_THROW(register_objective_term({"registry_test_unbuilt", false, {}, {}, nullptr}), std::logic_error);
}

}  // namespace
}  // namespace tailor::objective_term_registry_test
