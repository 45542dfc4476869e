// The reduced design loop (problems/fem/reduced_design.hpp): precomputed reduced forces against the
// projected full-space forces, the Taylor test of the reduced functional, the reduced design
// of a small handle scene against the full-space solve of the same design, and bad input.
#include "problems/fem/reduced_design.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "../../support/temp_folder.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "small_handle_scene.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::reduced_design_test {
namespace {

Vector parameters_at(const ReducedDesign& design, const Vector& w) {
  StaticSetup setup = design.setup;
  setup.youngs_modulus = design.youngs_modulus(w);
  return setup.parameters();
}

// Reference: ProjectedReducedModel, W(q) = E(x_rest + Phi q, p(w)) assembled over the mesh
// with the scene's StVK elements. The precomputed polynomial must agree to round-off.
TEST(ReducedDesign, PrecomputedForcesMatchProjectedFullForces) {
  for (const char* model : {"stvk", "linear"}) {
    const ReducedDesign design = build_reduced_design(small_handle_scene(model));
    const ReducedEquilibriumFunctional& f = *design.functional;
    ASSERT_GE(f.reduced_size(), 8);
    std::srand(3);
    const Vector w = 0.2 * Vector::Random(design.num_design());
    ASSERT_GT(design.youngs_modulus(w).minCoeff(), 0.0);
    // The elastic terms alone (the design's model also holds the handle loads).
    StaticSetup unloaded = design.setup;
    unloaded.has_loads = false;
    unloaded.nodal_forces.setZero();
    const std::unique_ptr<Model> elastic = build_static_model(unloaded, 1.0);
    const ProjectedReducedModel projected(*elastic, parameters_at(design, w), design.setup.rest_state(),
                                          design.basis);
    Vector q = Vector::Random(f.reduced_size());
    q *= 0.5 / design.reduced_displacement(q).cwiseAbs().maxCoeff();  // |u| up to 0.5 on a 5-long beam
    double e_reduced = 0.0, e_full = 0.0;
    Vector f_reduced, f_full;
    Matrix k_reduced, k_full;
    f.evaluate(q, w, &e_reduced, &f_reduced, &k_reduced);
    projected.evaluate(q, &e_full, &f_full, &k_full);
    EXPECT_NEAR(e_reduced, e_full, 1e-11 * std::abs(e_full)) << model;
    EXPECT_LT((f_reduced - f_full).norm(), 1e-10 * f_full.norm()) << model;
    EXPECT_LT((k_reduced - k_full).norm(), 1e-10 * k_full.norm()) << model;
  }
}

// The exact adjoint gradient of J(w) (Newton in q, adjoint in w), Taylor test at a design
// away from w = 0 and with the smoothness term on.
TEST(ReducedDesign, TaylorTestOfTheReducedFunctional) {
  for (const char* model : {"stvk", "linear"}) {
    ReducedDesign design =
        build_reduced_design(small_handle_scene(model, "[0, 0, -0.1]", R"(, "smoothness": 1e-3)"));
    std::srand(5);
    const Vector w = 0.2 * Vector::Random(design.num_design());
    const TaylorTestResult r = taylor_test(*design.functional, w);
    EXPECT_TRUE(r.passed()) << model << "\n" << r.message << "\n" << r.table();
    EXPECT_NEAR(r.rate0, 1.0, 0.1) << model;
    EXPECT_GE(r.rate1, 1.9) << model;
  }
}

// A reachable target: the full-space tip displacement of a known design w* (E halved near the
// root by the first two modes). The reduced design must reach it in reduced coordinates and,
// solved again in full space, within 1% (the reduction error at the designed material).
TEST(ReducedDesign, ReducedDesignMatchesTheFullSpaceSolve) {
  for (const char* model : {"stvk", "linear"}) {
    const ReducedDesign probe = build_reduced_design(small_handle_scene(model));
    Vector w_star = Vector::Zero(probe.num_design());
    w_star[0] = -0.5;
    w_star[1] = 0.1;
    const FullSpaceCheck truth = full_space_check(probe, w_star);
    ASSERT_TRUE(truth.converged) << truth.message;
    const int tip = probe.handles[0].vertices[0];
    const Vector u = truth.displacement.segment(3 * tip, 3);
    const std::string target =
        "[" + std::to_string(u[0]) + ", " + std::to_string(u[1]) + ", " + std::to_string(u[2]) + "]";
    ReducedDesign design = build_reduced_design(small_handle_scene(model, target));
    const std::string out = testing::unique_temp_path(std::string("reduced_design_test_") + model).string();
    const ReducedDesignRun run = run_reduced_design(design, out);
    ASSERT_FALSE(run.reduced_errors.empty());
    ASSERT_TRUE(run.full && run.full->converged);
    EXPECT_LT(run.reduced_errors[0], 1e-3) << model;
    EXPECT_LT(run.full->handle_errors[0], 1e-2) << model;
    EXPECT_TRUE(std::filesystem::exists(run.report_path));
  }
}

// A new target on a built design (set_handle_targets) is the design built for that target: the
// precomputation does not depend on it. Value and gradient agree with a fresh build at a design
// away from w = 0, they differ from the old target's (so the comparison can see a stale target),
// and the retargeted loop reaches a reachable target (the full-space response of a known design).
TEST(ReducedDesign, NewTargetsNeedNoNewPrecomputation) {
  ReducedDesign design = build_reduced_design(small_handle_scene("stvk", "[0, 0, -0.1]"));
  Vector w_star = Vector::Zero(design.num_design());
  w_star[0] = -0.4;
  w_star[1] = -0.1;
  const FullSpaceCheck truth = full_space_check(design, w_star);
  ASSERT_TRUE(truth.converged) << truth.message;
  const Vector u = truth.displacement.segment(3 * design.handles[0].vertices[0], 3);
  const std::string text =
      "[" + std::to_string(u[0]) + ", " + std::to_string(u[1]) + ", " + std::to_string(u[2]) + "]";
  ReducedDesign fresh = build_reduced_design(small_handle_scene("stvk", text));

  std::srand(11);
  const Vector w = 0.2 * Vector::Random(design.num_design());
  Vector g_old, g_new, g_fresh;
  const double j_old = design.functional->value_and_gradient(w, g_old);
  set_handle_targets(design, {fresh.handles[0].target});
  const double j_new = design.functional->value_and_gradient(w, g_new);
  const double j_fresh = fresh.functional->value_and_gradient(w, g_fresh);
  EXPECT_NEAR(j_new, j_fresh, 1e-12 * std::abs(j_fresh));
  EXPECT_LT((g_new - g_fresh).norm(), 1e-12 * g_fresh.norm());
  EXPECT_GT(std::abs(j_old - j_fresh), 1e-3 * std::abs(j_fresh));
  EXPECT_GT((g_old - g_fresh).norm(), 1e-3 * g_fresh.norm());

  const ReducedDesignRun run = run_reduced_design(design, "");
  ASSERT_FALSE(run.reduced_errors.empty());
  ASSERT_TRUE(run.full && run.full->converged);
  EXPECT_LT(run.reduced_errors[0], 1e-3);
  EXPECT_LT(run.full->handle_errors[0], 1e-2);

  // Bad targets: a count or size other than the handles', zero, not finite.
  EXPECT_THROW(set_handle_targets(design, {}), std::invalid_argument);
  EXPECT_THROW(set_handle_targets(design, {Vector::Ones(2)}), std::invalid_argument);
  EXPECT_THROW(set_handle_targets(design, {Vector::Zero(3)}), std::invalid_argument);
  EXPECT_THROW(set_handle_targets(design, {Vector::Constant(3, std::nan(""))}), std::invalid_argument);
  EXPECT_EQ(design.handles[0].target, fresh.handles[0].target);  // a refused target changes nothing
}

// Materials without a polynomial reduced energy take a cubature rule; its bad sizes are
// errors naming the key.
TEST(ReducedDesign, CubatureKeysAreChecked) {
  for (const char* bad : {R"(, "cubature": {"elements": 0})", R"(, "cubature": {"training_poses": 0})",
                          R"(, "cubature": {"tolerance": 0})", R"(, "cubature": {"element": 5})"}) {
    try {
      small_handle_scene("neo_hookean", "[0, 0, -0.1]", bad);
      FAIL() << "expected SceneError for " << bad;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("inverse.design.reduction.cubature"), std::string::npos)
          << e.what();
    }
  }
  // Called directly, a rule of no element is an std::invalid_argument naming the key.
  const ReducedDesign design = build_reduced_design(
      small_handle_scene("neo_hookean", "[0, 0, -0.1]", R"(, "cubature": {"elements": 10})"));
  CubatureSpec spec;
  spec.elements = 0;
  ReducedDesignCubature summary;
  try {
    fit_reduced_design_cubature(*design.model, design.setup.parameters(), design.basis, design.material_modes,
                                design.functional->data().load, spec, "inverse.design.reduction", summary);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("inverse.design.reduction.cubature"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at least 1"), std::string::npos) << e.what();
  }
}

TEST(ReducedDesign, SceneKeysAreChecked) {
  // The log map is not linear in w.
  std::string text = small_handle_scene_text("stvk", "[0, 0, -0.1]");
  text.replace(text.find("\"map\": \"identity\""), 17, "\"map\": \"log\"");
  EXPECT_THROW(parse_scene(text, "s.json", "."), SceneError);
  // Unknown key under reduction.
  EXPECT_THROW(
      parse_scene(small_handle_scene_text("stvk", "[0, 0, -0.1]", R"(, "cubatures": true)"), "s.json", "."),
      SceneError);
  try {
    parse_scene(small_handle_scene_text("stvk", "[0, 0, -0.1]", R"(, "min_relative_modulus": 2)"), "s.json",
                ".");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("inverse.design.reduction.min_relative_modulus"), std::string::npos)
        << e.what();
  }
}

// The shipped scene, run as `tailor run` does: its target is the full-space response of a 4x
// softer beam, so a design exists; the reduced loop (with its basis refinements) must reach it
// within 1% in full space.
TEST(ReducedDesign, ShippedSceneReachesItsTargetInFullSpace) {
  const Scene s = read_scene(std::string(::tailor::testing::test_data_dir()) +
                             "/../../scenes/cantilever_handle_reduced.json");
  ASSERT_TRUE(s.inverse && s.inverse->design.reduction);
  EXPECT_EQ(s.inverse->design.reduction->key, "inverse.design.reduction");
  const std::string out = testing::unique_temp_path("reduced_design_test_scene").string();
  const ReducedDesignRun run = run_reduced_design_scene(s, out);
  ASSERT_TRUE(run.full && run.full->converged);
  ASSERT_FALSE(run.passes.empty());
  EXPECT_LT(run.passes.back().full_error, 1e-2);
  EXPECT_LT(run.passes.back().reduced_error, 1e-2);
}

}  // namespace
}  // namespace tailor::reduced_design_test
