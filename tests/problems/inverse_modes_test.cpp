// Reduced material design with Laplacian material modes (granularity "modes"): Taylor tests of
// the reduced functional (linear and Neo-Hookean), the smooth box keeping E inside the bounds
// on an optimizer's result, r = "full" reproducing the per-element design, the initial design
// reproduced exactly, expression fields and the boundary selector, and scene errors.
#include "problems/fem/inverse_modes.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../support/temp_folder.hpp"
#include "adjoint/scaled_gradient.hpp"
#include "forward/mesh/generate.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/scene_selection.hpp"
#include "scene_text.hpp"

namespace tailor::inverse_modes_test {
namespace {

using TempFolder = tailor::testing::TempFolder;

// small_box_scene() (96 linear tets, E = 1000, pulled along x), optionally Neo-Hookean, with
// an inverse section.
Scene box_scene(const std::string& inverse, bool neo_hookean = false) {
  std::string text = testing::small_box_scene();
  if (neo_hookean) text = testing::with("\"model\": \"linear\"", "\"model\": \"neo_hookean\"", text);
  text = testing::with("\"traction\": [1, 0, 0]", "\"traction\": [60, 0, -20]", text);
  return parse_scene(testing::with("\"solver\": {\"load_steps\": 1}",
                                   "\"solver\": {\"load_steps\": 1},\n  \"inverse\": " + inverse, text),
                     "box.json", "");
}

// Observations of every vertex simulated with a stiff inclusion and a gradient (the truth).
std::string inverse_section(const std::string& design, const std::string& extra = "") {
  // Every design names the parameter; the tests give the rest.
  return R"({"design": {"parameter": "youngs_modulus", )" + design.substr(1) + R"(,
    "objective": [{"type": "synthetic_observations", "vertices": {"box": {"min": [0, 0, 0], "max": [2, 1, 1]}},
                   "youngs_modulus": {"value": 1000, "gradient": [0.3, 0, 0],
                                      "inclusions": [{"center": [1, 0.5, 0.5], "radius": 0.4, "factor": 3}]}}])" +
         extra + "}";
}

TEST(InverseModes, TaylorTestLinearAndNeoHookean) {
  for (const bool neo_hookean : {false, true}) {
    for (const char* map : {"log", "identity"}) {
      SCOPED_TRACE(std::string(neo_hookean ? "neo_hookean " : "linear ") + map);
      const Scene scene = box_scene(
          inverse_section(
              std::string(R"({"granularity": "modes", "modes": 6, "min": 200, "max": 5000, "map": ")") + map +
              "\"}"),
          neo_hookean);
      const auto problem = build_inverse_problem(scene);
      ASSERT_EQ(problem->num_design(), 6);
      ASSERT_TRUE(problem->modal);
      // Away from z = 0, so that every mode and the box's curvature take part.
      Vector z = Vector::LinSpaced(6, 0.3, -0.2);
      const TaylorTestResult result = taylor_test(*problem->functional, z);
      EXPECT_TRUE(result.passed()) << result.table();
      EXPECT_GE(result.rate1, 1.9) << result.table();
      if (neo_hookean && std::string(map) == "log") {
        ScaledGradient corrupted(*problem->functional, 1.01);  // 1% off: must be caught
        const TaylorTestResult wrong = taylor_test(corrupted, z);
        EXPECT_EQ(wrong.status, TaylorStatus::failed) << wrong.table();
      }
    }
  }
}

TEST(InverseModes, InitialDesignIsReproducedExactlyAndModesAreVOrthonormal) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 4, 2, 2);
  const int ne = mesh.num_elements();
  Eigen::VectorXd initial(ne);
  for (int e = 0; e < ne; ++e) initial[e] = 500.0 + 10.0 * e;  // not in the span of the modes
  ModalDesignOptions options;
  options.modes = 5;
  options.lower = 100.0;
  options.upper = 1e4;
  const ModalDesign design = modal_design(mesh, initial, options);
  EXPECT_EQ(design.modes.cols(), 5);
  EXPECT_LT((design.element_map->apply(design.z0) - initial).cwiseAbs().maxCoeff(),
            1e-9 * initial.maxCoeff());
  const Eigen::VectorXd volumes = element_volumes(mesh);
  const Matrix gram = design.modes.transpose() * volumes.asDiagonal() * design.modes;
  EXPECT_LT((gram - Matrix::Identity(5, 5)).cwiseAbs().maxCoeff(), 1e-8);
  // On the bound is not strictly inside: the smooth box never reaches it.
  initial[3] = 100.0;
  EXPECT_THROW(modal_design(mesh, initial, options), std::invalid_argument);
}

// The truth (up to 3000 in the inclusion) lies partly above max = 1500: the optimizer pushes
// against the bound, which the smooth box keeps exactly (no element above it, none below min).
TEST(InverseModes, BoundsHoldExactlyOnTheResult) {
  TempFolder folder("inverse_modes_bounds");
  const Scene scene = box_scene(inverse_section(
      R"({"granularity": "modes", "modes": 8, "min": 900, "max": 1500})",
      R"(, "optimizer": {"backend": "nlopt_lbfgs", "max_iterations": 60, "gradient_tolerance": 1e-12})"));
  const InverseRun run = run_inverse_scene(scene, folder / "out");
  ASSERT_GT(run.result.history.size(), 5u) << run.result.report();
  EXPECT_LE(run.youngs_modulus.maxCoeff(), 1500.0);
  EXPECT_GE(run.youngs_modulus.minCoeff(), 900.0);
  EXPECT_GT(run.youngs_modulus.maxCoeff(), 1400.0);  // it did push against the bound
  ASSERT_TRUE(run.error);
  EXPECT_LT(run.error->relative_l2, run.initial_error->relative_l2);
}

// Without bounds and with the log map, "full" is the per-element design: the same J and dJ/dz
// at the start, and the same optimizer path.
TEST(InverseModes, FullReproducesPerElementDesign) {
  TempFolder folder("inverse_modes_full");
  const std::string optimizer = R"(, "optimizer": {"max_iterations": 15})";
  const Scene full = box_scene(inverse_section(R"({"granularity": "modes", "modes": "full"})", optimizer));
  const Scene element = box_scene(inverse_section(R"({"granularity": "per_element"})", optimizer));
  const auto a = build_inverse_problem(full);
  const auto b = build_inverse_problem(element);
  ASSERT_EQ(a->num_design(), b->num_design());
  EXPECT_LT((a->z0 - b->z0).cwiseAbs().maxCoeff(), 1e-12);
  Vector ga, gb;
  EXPECT_DOUBLE_EQ(a->functional->value_and_gradient(a->z0, ga),
                   b->functional->value_and_gradient(b->z0, gb));
  EXPECT_LT((ga - gb).norm(), 1e-12 * gb.norm());
  const InverseRun ra = run_inverse_scene(full, folder / "full");
  const InverseRun rb = run_inverse_scene(element, folder / "element");
  EXPECT_LT((ra.youngs_modulus - rb.youngs_modulus).cwiseAbs().maxCoeff(),
            1e-8 * rb.youngs_modulus.maxCoeff());
  EXPECT_EQ(ra.result.history.size(), rb.result.history.size());
}

TEST(InverseModes, ExpressionFieldAndBoundarySelector) {
  const auto problem =
      build_inverse_problem(box_scene(inverse_section(R"({"granularity": "modes", "modes": 3})")));
  const Mesh& mesh = problem->setup.mesh;
  ASSERT_EQ(problem->truth.size(), mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += mesh.rest_positions.row(mesh.elements(e, k)).transpose() / 4.0;
    const double inside = (c - Eigen::Vector3d(1, 0.5, 0.5)).norm() <= 0.4 ? 3.0 : 1.0;
    EXPECT_NEAR(problem->truth[e], 1000.0 * (1.0 + 0.3 * c.x()) * inside, 1e-9);
  }
  // 5 x 3 x 3 vertices, 3 of them inside.
  const Scene scene = box_scene(inverse_section(R"({"granularity": "modes", "modes": 3})"));
  VertexSelector boundary;
  boundary.kind = VertexSelector::Kind::boundary;
  EXPECT_EQ(select_vertices(scene, mesh, boundary).size(), 42u);
}

TEST(InverseModes, SceneErrorsNameTheKey) {
  const auto expect_error = [](const std::string& design, const std::string& fragment) {
    try {
      build_inverse_problem(box_scene(inverse_section(design)));
      ADD_FAILURE() << "no error for " << design;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"granularity": "modes", "modes": 4, "min": 10})", "inverse.design.min: with granularity");
  expect_error(R"({"granularity": "modes", "modes": 4, "map": "identity"})", "needs min and max");
  expect_error(R"({"granularity": "modes", "modes": 96})", "inverse.design.modes");
  expect_error(R"({"granularity": "modes", "modes": 0})", "inverse.design.modes");
  expect_error(R"({"granularity": "modes", "modes": "all"})", "inverse.design.modes");
  expect_error(R"({"granularity": "modes", "modes": 4, "output_modes": 5})", "inverse.design.output_modes");
  expect_error(R"({"granularity": "per_element", "modes": 4})", "inverse.design.modes: only with");
  expect_error(R"({"granularity": "modes", "modes": 4, "min": 1000, "max": 2000})", "strictly inside");
}

}  // namespace
}  // namespace tailor::inverse_modes_test
