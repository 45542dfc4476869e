// The "optimizer" section (problems/optimizer_section.hpp): one parser with one set of rules,
// and the same section gives the same options in every kind that optimizes.
#include "problems/optimizer_section.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../support/temp_folder.hpp"
#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/scene.hpp"
#include "problems/homogenization/cell_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/material_fit/material_fit_scene.hpp"
#include "problems/metamaterial/metamaterial_scene.hpp"
#include "problems/rods/rod_inverse.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"

namespace tailor::optimizer_section_test {
namespace {

const std::string kSource = "scene.json";

OptimizerOptions parse(const std::string& section, const OptimizerSectionSupport& support = {},
                       OptimizerOptions defaults = {}) {
  const nlohmann::json document = parse_json(section);
  return parse_optimizer_section(SceneNode(document, kSource, "optimizer"), defaults, support);
}

std::string error(const std::string& section, const OptimizerSectionSupport& support = {}) {
  try {
    parse(section, support);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

// The first registered back-end with (or without) a capability; nullptr when there is none.
const BackendEntry* backend_where(bool BackendCapabilities::*capability, bool has) {
  for (const BackendEntry* entry : registered_backends())
    if (entry->capabilities.*capability == has) return entry;
  return nullptr;
}

TEST(OptimizerSection, KeysNotGivenKeepTheKindsDefaults) {
  OptimizerOptions defaults;
  defaults.backend = OptimizerBackend::gradient_descent;
  defaults.max_iterations = 7;
  defaults.gradient_tolerance = 0.5;
  const OptimizerOptions o = parse("{}", {}, defaults);
  EXPECT_EQ(o.backend, OptimizerBackend::gradient_descent);
  EXPECT_EQ(o.max_iterations, 7);
  EXPECT_EQ(o.gradient_tolerance, 0.5);
  EXPECT_EQ(o.objective_tolerance, defaults.objective_tolerance);
  EXPECT_EQ(o.checkpoint_every, defaults.checkpoint_every);
}

TEST(OptimizerSection, EveryKey) {
  const OptimizerOptions o = parse(
      R"({"backend": "gradient_descent", "max_iterations": 3, "gradient_tolerance": 1e-3,
          "objective_tolerance": 1e-4, "step_tolerance": 1e-5, "time_limit": 60, "checkpoint_every": 0})",
      {"this scene", false, true, {}});
  EXPECT_EQ(o.backend, OptimizerBackend::gradient_descent);
  EXPECT_EQ(o.max_iterations, 3);
  EXPECT_EQ(o.gradient_tolerance, 1e-3);
  EXPECT_EQ(o.objective_tolerance, 1e-4);
  EXPECT_EQ(o.step_tolerance, 1e-5);
  EXPECT_EQ(o.time_limit_seconds, 60.0);
  EXPECT_EQ(o.checkpoint_every, 0);
}

TEST(OptimizerSection, TolerancesAndTimeLimitAreNonNegative) {
  for (const char* key : {"gradient_tolerance", "objective_tolerance", "step_tolerance", "time_limit"}) {
    EXPECT_EQ(error(std::string("{\"") + key + "\": 0}"), "") << key;
    EXPECT_EQ(error(std::string("{\"") + key + "\": -1e-9}"),
              kSource + ": optimizer." + key + ": expected a number >= 0, got -1e-09");
  }
}

TEST(OptimizerSection, IterationsAndCheckpointsAreCounts) {
  EXPECT_EQ(error(R"({"max_iterations": 1})"), "");
  EXPECT_EQ(error(R"({"max_iterations": 0})"),
            kSource + ": optimizer.max_iterations: expected an integer >= 1, got 0");
  EXPECT_EQ(error(R"({"max_iterations": 2.5})"),
            kSource + ": optimizer.max_iterations: expected an integer >= 1, got 2.5");
  const OptimizerSectionSupport checkpoints{"this scene", false, true, {}};
  EXPECT_EQ(error(R"({"checkpoint_every": 0})", checkpoints), "");
  EXPECT_EQ(error(R"({"checkpoint_every": -1})", checkpoints),
            kSource + ": optimizer.checkpoint_every: expected an integer >= 0, got -1");
}

TEST(OptimizerSection, TheBackendIsARegisteredOne) {
  const std::string e = error(R"({"backend": "simplex"})");
  EXPECT_EQ(e.rfind(kSource + ": optimizer.backend: ", 0), 0u) << e;
  for (const BackendEntry* entry : registered_backends())
    EXPECT_NE(e.find(entry->name), std::string::npos) << e;  // the registered ones are listed
}

TEST(OptimizerSection, ExactHessianNeedsABackendThatUsesIt) {
  const OptimizerSectionSupport hessians{"this scene", true, false, {}};
  const BackendEntry* without = backend_where(&BackendCapabilities::exact_hessian, false);
  ASSERT_NE(without, nullptr);
  EXPECT_EQ(error(R"({"backend": ")" + without->name + R"(", "exact_hessian": false})", hessians), "");
  EXPECT_EQ(error(R"({"backend": ")" + without->name + R"(", "exact_hessian": true})", hessians),
            kSource + ": optimizer.exact_hessian: only the " +
                backends_with(&BackendCapabilities::exact_hessian) +
                " back-end uses exact Hessians (the back-end is " + without->name + ")");
  if (const BackendEntry* with = backend_where(&BackendCapabilities::exact_hessian, true)) {
    EXPECT_TRUE(
        parse(R"({"backend": ")" + with->name + R"(", "exact_hessian": true})", hessians).exact_hessian);
  }
}

TEST(OptimizerSection, KeysTheKindCannotHonourAreRefusedSayingSo) {
  const OptimizerSectionSupport rods{"a rod scene", false, false, {}};
  EXPECT_EQ(error(R"({"checkpoint_every": 5})", rods),
            kSource + ": optimizer.checkpoint_every: a rod scene writes no optimizer checkpoints");
  EXPECT_EQ(error(R"({"exact_hessian": false})", rods),
            kSource +
                ": optimizer.exact_hessian: a rod scene cannot use exact Hessians (its optimization has no "
                "Hessian-vector products or has constraints)");
  // Misspelled: an unknown key, with the keys the kind takes.
  EXPECT_EQ(error(R"({"max_iteration": 5})", rods),
            kSource +
                ": optimizer.max_iteration: unknown key (allowed here: backend, max_iterations, "
                "gradient_tolerance, objective_tolerance, step_tolerance, time_limit)");
  EXPECT_NE(error(R"({"max_iteration": 5})", {"this scene", true, true, {}})
                .find("time_limit, exact_hessian, checkpoint_every)"),
            std::string::npos);
  EXPECT_EQ(error("[]", rods), kSource + ": optimizer: expected an object, got an array of 0");
}

TEST(OptimizerSection, ABackendWithoutWhatTheKindNeedsIsRefused) {
  OptimizerSectionSupport design{"a cell design", false, false, {}};
  design.needs.bounds = design.needs.inequality_constraints = true;
  const BackendEntry* unbounded = backend_where(&BackendCapabilities::bounds, false);
  ASSERT_NE(unbounded, nullptr);
  EXPECT_EQ(error(R"({"backend": ")" + unbounded->name + R"("})", design),
            kSource + ": optimizer.backend: " + unbounded->name +
                " does not support bounds, which a cell design needs (choose one of " +
                backends_with(&BackendCapabilities::bounds) + ")");
}

// One section in the FEM inverse problem, a rod design, a material fit and a cell design: the
// same options in each.
TEST(OptimizerSection, TheSameSectionGivesTheSameOptionsInEveryKind) {
  const BackendEntry* backend = nullptr;  // one that every kind takes: bounds and constraints
  for (const BackendEntry* entry : registered_backends())
    if (entry->capabilities.bounds && entry->capabilities.inequality_constraints) backend = entry;
  ASSERT_NE(backend, nullptr);
  const nlohmann::json section = {{"backend", backend->name},   {"max_iterations", 17},
                                  {"gradient_tolerance", 1e-7}, {"objective_tolerance", 1e-6},
                                  {"step_tolerance", 1e-5},     {"time_limit", 30}};
  const auto with_section = [&](const std::string& scene, const std::string& pointer) {
    nlohmann::json document = read_scene_document(testing::kScenesDir + "/" + scene);
    document[nlohmann::json::json_pointer(pointer)] = section;
    return document;
  };
  std::vector<OptimizerOptions> parsed;
  const nlohmann::json fem = with_section("two_material_bar_inverse.json", "/inverse/optimizer");
  parsed.push_back(parse_scene(SceneNode(fem, kSource, ""), testing::kScenesDir).inverse->optimizer);
  const nlohmann::json rods = with_section("rods/rod_stiffness_design.json", "/inverse/optimizer");
  parsed.push_back(build_rod_inverse(rods, kSource, "rods")->spec.optimizer);
  const nlohmann::json fit = with_section("material_fit/spline_fit_neo_hookean.json", "/optimizer");
  parsed.push_back(parse_material_fit_scene(SceneNode(fit, kSource, "")).optimizer);
  const nlohmann::json cell = with_section("homogenization/auxetic_2d.json", "/design/optimizer");
  const SceneNode root(cell, kSource, "");
  parsed.push_back(parse_metamaterial_design(root, parse_cell_scene(root, testing::kScenesDir)).optimizer);
  for (const OptimizerOptions& o : parsed) {
    EXPECT_EQ(o.backend, parse_optimizer_backend(backend->name));
    EXPECT_EQ(o.max_iterations, 17);
    EXPECT_EQ(o.gradient_tolerance, 1e-7);
    EXPECT_EQ(o.objective_tolerance, 1e-6);
    EXPECT_EQ(o.step_tolerance, 1e-5);
    EXPECT_EQ(o.time_limit_seconds, 30.0);
    EXPECT_FALSE(o.exact_hessian);
  }
}

}  // namespace
}  // namespace tailor::optimizer_section_test
