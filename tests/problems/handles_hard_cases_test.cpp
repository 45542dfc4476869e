// Hard cases of material design with handles:
//  - moduli 1e4 apart solve accurately: a two-material bar in series against the closed form
//    F = u / (L1 / (E1 A) + L2 / (E2 A)) (uniaxial stress, nu = 0);
//  - bounds on E hold exactly in the result when the targets ask for more;
//  - inconsistent force and displacement targets converge to the compromise the weights ask
//    for, checked on one tetrahedron whose free vertex has the scalar stiffness k = E V
//    (nu = 0, right-corner tet): argmin a/2 W (k u - f)^2 + a b/2 (u - ubar)^2
//    = (W k f + b ubar) / (W k^2 + b);
//  - supports plus handles that leave a rigid motion free are rejected with a message.
#include <gtest/gtest.h>

#include <cmath>

#include "../support/temp_folder.hpp"
#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/reduction/free_space.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/inverse_handles.hpp"
#include "scene_text.hpp"

namespace tailor::handles_hard_cases_test {
namespace {

using TempFolder = tailor::testing::TempFolder;

// A 2 x 1 x 1 bar (4 x 1 x 1 cells), nu = 0, E1 on x < 1 and E2 on x > 1, supported by rollers
// at x = 0 (statically determinate: uniaxial stress is exact); the handle is the x = 2 face.
std::string series_bar(double E1, double E2, const std::string& design, const std::string& handle_targets,
                       const std::string& beta = "1", const std::string& optimizer = "") {
  return R"({
  "mesh": {"box": {"min": [0, 0, 0], "max": [2, 1, 1], "cells": [4, 1, 1]}},
  "materials": [
    {"elements": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}, "model": "linear", "youngs_modulus": )" +
         std::to_string(E1) + R"(, "poisson_ratio": 0},
    {"elements": {"box": {"min": [1, 0, 0], "max": [2, 1, 1]}}, "model": "linear", "youngs_modulus": )" +
         std::to_string(E2) + R"(, "poisson_ratio": 0}
  ],
  "dirichlet": [
    {"vertices": {"plane": {"axis": "x", "value": 0}}, "components": [0]},
    {"vertices": {"list": [0]}, "components": [1, 2]},
    {"vertices": {"box": {"min": [0, 1, 0], "max": [0, 1, 0]}}, "components": [2]},
    {"vertices": {"box": {"min": [0, 0, 1], "max": [0, 0, 1]}}, "components": [1]}
  ],
  "inverse": {
    "design": )" +
         design + R"(,
    "objective": [{"type": "handles", "beta": )" +
         beta + R"(, "handles": [{"vertices": {"plane": {"axis": "x", "value": 2}}, )" + handle_targets +
         R"(}]}])" + optimizer + R"(
  }
})";
}

TEST(HandlesHardCases, ModuliFourDecadesApartMatchTheSeriesBarClosedForm) {
  for (const auto& [E1, E2] : {std::pair{1.0, 1e4}, std::pair{1e4, 1.0}}) {
    const double u = 1e-3;
    const auto problem = build_inverse_problem(
        parse_scene(series_bar(E1, E2, R"({"parameter": "youngs_modulus", "granularity": "per_material"})",
                               R"("displacement": [0.001, 0, 0])"),
                    "bar.json", ""));
    problem->functional->value(problem->z0);
    const Vector p = problem->parameterization->apply(problem->z0);
    const double closed_form = u / (1.0 / E1 + 1.0 / E2);  // A = 1, L1 = L2 = 1
    const Vector force = problem->handles->objective->total_force(0, problem->functional->state(), p);
    EXPECT_NEAR(force[0] / closed_form, 1.0, 1e-8) << "E1 = " << E1 << ", E2 = " << E2;
    EXPECT_LT(std::abs(force[1]) + std::abs(force[2]), 1e-9 * closed_form);
  }
}

TEST(HandlesHardCases, SoftAndStiffMaterialsAreRecoveredFromForceAndDisplacement) {
  // Targets from E1 = 1, E2 = 1e4 (force 1e-3 / (1 + 1e-4)); the soft part starts 10x off and
  // is the only thing that matters for the force: the optimum matches both targets.
  const double force = 1e-3 / (1.0 + 1e-4);
  const std::string targets =
      R"("displacement": [0.001, 0, 0], "force": [)" + std::to_string(force) + R"(, 0, 0], "weight": 1e8)";
  TempFolder folder("handles_series");
  const InverseRun run = run_inverse_scene(
      parse_scene(series_bar(10.0, 1e4, R"({"parameter": "youngs_modulus", "granularity": "per_material"})",
                             targets, "1e12", R"(, "optimizer": {"gradient_tolerance": 1e-12})"),
                  "bar.json", ""),
      folder / "out");
  ASSERT_EQ(run.handles.size(), 1u);
  EXPECT_TRUE(run.result.z.allFinite());
  EXPECT_LT(run.handles[0].relative_force_error, 1e-4) << run.result.report();
  EXPECT_LT(run.handles[0].relative_displacement_error, 1e-4);
  EXPECT_NEAR(run.design_values[0], 1.0, 1e-3)
      << run.result.report();  // the series compliance is 1/E1 + 1/E2
}

TEST(HandlesHardCases, BoundsOnTheModulusHoldExactly) {
  // The target force asks for E = 1000 (series of two equal halves: F = u E / 2), the bounds
  // allow [30, 300]: both materials end on the upper bound, not beyond. beta = 1e13 >> W k^2
  // ~ 1e6 * 50^2 keeps u~ at ubar, so only E can reduce the force misfit.
  TempFolder folder("handles_bounds");
  const InverseRun run = run_inverse_scene(
      parse_scene(series_bar(100, 100, R"({"parameter": "youngs_modulus", "granularity": "per_material",
                                          "min": 30, "max": 300})",
                             R"("displacement": [0.001, 0, 0], "force": [0.5, 0, 0], "weight": 1e6)", "1e13"),
                  "bar.json", ""),
      folder / "out");
  ASSERT_EQ(run.design_values.size(), 2);
  for (Eigen::Index k = 0; k < 2; ++k) {
    EXPECT_LE(run.design_values[k], 300.0);
    EXPECT_GE(run.design_values[k], 30.0);
    EXPECT_NEAR(run.design_values[k], 300.0, 1e-12 * 300.0) << run.result.report();
  }
  EXPECT_LE(run.youngs_modulus.maxCoeff(), 300.0);
  EXPECT_LE(run.result.z.head(2).maxCoeff(), std::log(300.0));  // z itself never leaves the box
}

// One right-corner tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) with vertices 0, 2, 3 clamped
// and vertex 1 the handle; linear material with nu = 0. Vertex 1's stiffness block is
// V diag(2 mu + lambda, mu, mu) = diag(E V, E V / 2, E V / 2), V = 1/6. A mirrored tet through
// vertex 4 = (-1,0,0) gives the equilibrium solve free DOFs without touching vertex 1.
struct OneTet {
  Mesh mesh;
  std::unique_ptr<Model> model;
  std::shared_ptr<HandleObjective> objective;
  Vector rest;

  OneTet(double E, double force, double displacement, double weight, double alpha, double beta) {
    mesh.rest_positions = Eigen::MatrixXd{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}};
    mesh.elements = Eigen::MatrixXi{{0, 1, 2, 3}, {0, 4, 3, 2}};
    mesh.element_regions = Eigen::VectorXi::Zero(2);
    model = std::make_unique<Model>(15);
    model->parameter_layout().add("youngs_modulus", 2);
    model->parameter_layout().add("poisson_ratio", 2);
    auto elastic = std::make_shared<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::linear), 0, 2);
    model->add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::linear), 0, 2));
    rest = Eigen::Map<const Vector>(Eigen::MatrixXd(mesh.rest_positions.transpose()).data(), 15);
    Handle handle;
    handle.vertices = {1};
    handle.target_force = Eigen::Vector3d(force, 0, 0);
    handle.target_displacement = Eigen::RowVector3d(displacement, 0, 0);
    handle.weight = weight;
    objective = std::make_shared<HandleObjective>(std::vector<std::shared_ptr<const EnergyTerm>>{elastic}, 15,
                                                  3, std::vector<Handle>{handle}, 4,
                                                  HandleObjectiveOptions{alpha, beta});
    model->set_elimination(Elimination::dirichlet({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}, rest));
    model->add_prescribed_displacements("handle_displacement", objective->dofs());
    base = Vector(7);
    base << E, E, 0.0, 0.0, 0.0, 0.0, 0.0;
  }
  Vector base;
};

TEST(HandlesHardCases, InconsistentTargetsConvergeToTheWeightedCompromise) {
  const double E = 600.0, k = E / 6.0, f = 50.0, ubar = 0.1;  // k ubar = 10: 5x off the force
  for (const auto& [W, beta] :
       {std::pair{1.0, 1.0}, std::pair{1.0, 1e4}, std::pair{1e-3, 1.0}, std::pair{1e3, 1.0}}) {
    SCOPED_TRACE("W = " + std::to_string(W) + ", beta = " + std::to_string(beta));
    OneTet tet(E, f, ubar, W, 0.5, beta);
    // Design: u~ only (E fixed), so the stiffness k is fixed.
    const auto map = embed_blocks(tet.base, {{4, identity_map(3)}});
    StaticFunctional functional(*tet.model, map, tet.objective, Vector(tet.rest.tail(3)));
    OptimizerOptions options;
    options.gradient_tolerance = 1e-12;
    const OptimizerResult result = minimize(functional, Vector::Zero(3), {}, {}, options);
    ASSERT_TRUE(result.z.allFinite());
    const double expected = (W * k * f + beta * ubar) / (W * k * k + beta);
    EXPECT_NEAR(result.z[0], expected, 1e-6 * std::abs(expected)) << result.report();
    EXPECT_NEAR(result.z[1], 0.0, 1e-9);
    EXPECT_NEAR(result.z[2], 0.0, 1e-9);
    // The reaction is k u~ (the formula's K~ u~ with no free DOFs).
    const Vector p = map->apply(result.z);
    EXPECT_NEAR(tet.objective->total_force(0, tet.model->state(Vector(tet.rest.tail(3)), p), p)[0],
                k * result.z[0], 1e-9 * k * std::abs(expected));
  }
}

// Rigid motions of the mesh that leave every listed DOF unmoved (forward/reduction/free_space.hpp).
int free_rigid_motions(const Mesh& mesh, const std::vector<int>& constrained_dofs) {
  return static_cast<int>(unconstrained_rigid_motions(mesh, constrained_dofs).size());
}

TEST(HandlesHardCases, RigidMotionLeftFreeIsRejected) {
  const Mesh box = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 2, 1, 1);
  auto dofs_of = [](std::vector<int> vertices, int dim) {
    std::vector<int> dofs;
    for (int v : vertices)
      for (int k = 0; k < dim; ++k) dofs.push_back(dim * v + k);
    return dofs;
  };
  // Vertex ids i + 3 (j + 2 k): 0 (0,0,0), 1 (1,0,0), 2 (2,0,0), 3 (0,1,0), 6 (0,0,1).
  EXPECT_EQ(free_rigid_motions(box, {}), 6);
  EXPECT_EQ(free_rigid_motions(box, dofs_of({0}, 3)), 3);               // rotations about the vertex
  EXPECT_EQ(free_rigid_motions(box, dofs_of({0, 1, 2}, 3)), 1);         // collinear: the axis rotation
  EXPECT_EQ(free_rigid_motions(box, dofs_of({0, 1, 3}, 3)), 0);         // three non-collinear
  EXPECT_EQ(free_rigid_motions(box, {0, 1, 2, 9, 11, 18, 19, 27}), 0);  // determinate rollers
  // A DOF beyond the mesh's vertices (e.g. a quadratic mesh's edge node) is an error, not a read
  // past the positions.
  EXPECT_THROW(free_rigid_motions(box, {0, 1, 2, 3 * box.num_vertices()}), std::invalid_argument);
  const Mesh plate = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 2, 1);
  EXPECT_EQ(free_rigid_motions(plate, dofs_of({0}, 2)), 1);
  EXPECT_EQ(free_rigid_motions(plate, dofs_of({0, 1}, 2)), 0);  // two distinct vertices

  // In a scene: no supports and one handle vertex.
  const std::string single = R"({
  "mesh": {"box": {"min": [0, 0, 0], "max": [2, 1, 1], "cells": [2, 1, 1]}},
  "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 100, "poisson_ratio": 0.3}],
  "loads": {"nodal": [{"vertices": {"list": [2]}, "force": [1, 0, 0]}]},
  "inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "per_material"},
    "objective": [{"type": "handles", "handles": [{"vertices": {"list": [0]}, "force": [-1, 0, 0]}]}]
  }
})";
  std::string message;
  try {
    build_inverse_problem(parse_scene(single, "free.json", ""));
  } catch (const SceneError& e) {
    message = e.what();
  }
  EXPECT_NE(
      message.find("free.json: inverse.objective[0]: the dirichlet conditions and the handles leave the body "
                   "free to move rigidly (3 independent rigid motions"),
      std::string::npos)
      << message;
  EXPECT_NE(message.find("at least 3 non-collinear vertices"), std::string::npos) << message;
  // Three non-collinear handle vertices pin it.
  std::string pinned = single;
  pinned.replace(pinned.find("{\"list\": [0]}"), 13, "{\"list\": [0, 1, 3]}");
  EXPECT_NO_THROW(build_inverse_problem(parse_scene(pinned, "free.json", "")));
}

}  // namespace
}  // namespace tailor::handles_hard_cases_test
