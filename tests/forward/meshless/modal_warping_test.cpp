// Modal warping (Choi & Ko 2005) on meshless modes: W(w) against quadrature of its definition,
// a 90-degree rigid rotation represented exactly by the warped linearized rotation where the
// linear mode distorts by a measured amount, and the Rayleigh-damped modal step against the
// closed-form damped oscillator (Chopra, Dynamics of Structures, eq. 2.2.4); rotation and position
// handles in the warped dynamics (the rigid rotation the reference).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "forward/fem/material_registry.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "forward/meshless/modal_warping.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "meshless_fixtures.hpp"

namespace tailor::modal_warping_test {
namespace {

using namespace tailor::meshless_testing;

TEST(ModalWarping, WarpingMatrixIsTheIntegralOfTheRotation) {
  for (const Eigen::Vector3d& w : {Eigen::Vector3d(0.3, -0.2, 1.1), Eigen::Vector3d(1e-5, 2e-5, 0.0), Eigen::Vector3d(0, 0, M_PI)}) {
    // Simpson's rule on exp(s [w]x), 2000 intervals.
    Eigen::Matrix3d integral = Eigen::Matrix3d::Zero();
    const int n = 2000;
    for (int i = 0; i <= n; ++i) {
      const double c = i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0;
      integral += c * rotation_matrix(w * (static_cast<double>(i) / n));
    }
    integral /= 3.0 * n;
    EXPECT_LT((warping_matrix(w) - integral).cwiseAbs().maxCoeff(), 1e-12) << w.transpose();
    const Eigen::Matrix3d R = rotation_matrix(w);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_LT((R - Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()).norm(), 1e-14);
  }
}

TEST(ModalWarping, NinetyDegreeRotationIsExactWhereTheLinearModeDistorts) {
  // A 2 x 1 x 1 box (h = 0.5, 45 nodes); the "mode" is the linearized rotation about the z axis
  // through the centre, u_b = e_z x (X_b - c) per node coefficient. MLS reproduces the linear
  // field, so at any point u_L = e_z x (X - c) and w = 1/2 curl u_L = e_z.
  const MeshlessSolid s = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1)), 0.5, 2, 0);
  const Eigen::Vector3d c(1.0, 0.5, 0.5), e(0, 0, 1);
  const int n = s.num_nodes();
  Eigen::MatrixXd mode(3 * n, 1);
  for (int b = 0; b < n; ++b) mode.block<3, 1>(3 * b, 0) = e.cross(Eigen::Vector3d(s.sampling.nodes.row(b).transpose() - c));
  // Evaluation points: the nodes and 50 random points inside.
  Eigen::MatrixXd points(n + 50, 3);
  points.topRows(n) = s.sampling.nodes;
  for (int i = 0; i < 50; ++i)
    points.row(n + i) = (Eigen::Vector3d::Random().cwiseAbs().cwiseProduct(Eigen::Vector3d(2, 1, 1))).transpose();
  const ModalWarpingOperators ops = modal_warping_operators(*s.mls, mode, points);
  for (int i = 0; i < ops.num_points(); ++i) EXPECT_LT((ops.rotation.block<3, 1>(3 * i, 0) - e).norm(), 1e-12) << i;

  const double theta = M_PI / 2;
  WarpedModalSimulator sim(ops, Eigen::VectorXd::Ones(1), {}, 0.01);
  sim.set_state(Eigen::VectorXd::Constant(1, theta), Eigen::VectorXd::Zero(1));
  Eigen::VectorXd warped, linear;
  sim.displacements(warped, true);
  sim.displacements(linear, false);
  const Eigen::Matrix3d R = rotation_matrix(theta * e);
  double warped_error = 0.0, linear_error = 0.0, largest_stretch = 0.0;
  for (int i = 0; i < ops.num_points(); ++i) {
    const Eigen::Vector3d X = points.row(i).transpose() - c;
    const Eigen::Vector3d exact = (R - Eigen::Matrix3d::Identity()) * X;
    warped_error = std::max(warped_error, (warped.segment<3>(3 * i) - exact).norm());
    linear_error = std::max(linear_error, (linear.segment<3>(3 * i) - exact).norm() / std::max(X.norm(), 1e-12));
    // Stretch of the radius vector in the plane of rotation: sqrt(1 + theta^2) - 1 for the linear map.
    const Eigen::Vector3d planar(X[0], X[1], 0.0);
    if (planar.norm() > 0.1) {
      const Eigen::Vector3d moved = planar + linear.segment<3>(3 * i);
      largest_stretch = std::max(largest_stretch, moved.norm() / planar.norm() - 1.0);
    }
  }
  std::printf("90-degree rotation at %d points: warped error %.2e (absolute); linear mode error %.3f of |X - c|, "
              "radial stretch %.4f (theory sqrt(1 + (pi/2)^2) - 1 = %.4f)\n",
              ops.num_points(), warped_error, linear_error, largest_stretch, std::sqrt(1.0 + theta * theta) - 1.0);
  EXPECT_LT(warped_error, 1e-12);
  EXPECT_NEAR(largest_stretch, std::sqrt(1.0 + theta * theta) - 1.0, 1e-12);
  EXPECT_GT(linear_error, 0.5);  // the check can fail: the linear field is far from the rotation

  // A force applied at a point in the rotated configuration acts in the local frame: a force
  // along the rotated tangent R e_x... (here: along R applied to the mode's own direction at
  // that point) has the full modal component, the unrotated one none.
  const int i = n;  // the first random point
  const Eigen::Vector3d tangent = ops.displacement.block<3, 1>(3 * i, 0);
  EXPECT_NEAR(sim.modal_force(i, R * tangent)[0], tangent.squaredNorm(), 1e-12);
  EXPECT_NEAR(sim.modal_force(i, tangent)[0], tangent.dot(R.transpose() * tangent), 1e-12);
}

// Warping on P1 tet modes: the per-vertex rotation is the volume-weighted average of the tets'
// constant 1/2 curl. For a linear field u = G X every tet has the exact curl, so every vertex
// gets w = 1/2 (G32 - G23, G13 - G31, G21 - G12); a linearized 90-degree rotation is then warped
// into the exact one at every vertex. A quadratic field u = (0, 0, x^2) (half curl (0, -x, 0))
// is recovered to O(h): the largest vertex error halves when the mesh is refined.
TEST(ModalWarping, FemModesCurlFromTheTetGradients) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 4, 2, 2);
  const int n = mesh.num_vertices();
  const Eigen::Vector3d c(1.0, 0.5, 0.5), e = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  Eigen::Matrix3d G;
  G << 0.3, -1.2, 0.4, 0.7, -0.1, 2.0, -0.6, 0.9, 0.5;
  Eigen::MatrixXd modes(3 * n, 2);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d X = mesh.rest_positions.row(i).transpose();
    modes.block<3, 1>(3 * i, 0) = e.cross(X - c);
    modes.block<3, 1>(3 * i, 1) = G * X;
  }
  const ModalWarpingOperators ops = fem_modal_warping_operators(mesh, modes);
  const Eigen::Vector3d half_curl_G = 0.5 * Eigen::Vector3d(G(2, 1) - G(1, 2), G(0, 2) - G(2, 0), G(1, 0) - G(0, 1));
  for (int i = 0; i < n; ++i) {
    EXPECT_LT((ops.rotation.block<3, 1>(3 * i, 0) - e).norm(), 1e-12) << i;
    EXPECT_LT((ops.rotation.block<3, 1>(3 * i, 1) - half_curl_G).norm(), 1e-12) << i;
    EXPECT_EQ((ops.displacement.middleRows(3 * i, 3) - modes.middleRows(3 * i, 3)).norm(), 0.0);
  }
  const double theta = M_PI / 2;
  WarpedModalSimulator sim(ops, Eigen::VectorXd::Ones(2), {}, 0.01);
  sim.set_state(Eigen::Vector2d(theta, 0.0), Eigen::VectorXd::Zero(2));
  Eigen::VectorXd warped, linear;
  sim.displacements(warped, true);
  sim.displacements(linear, false);
  const Eigen::Matrix3d R = rotation_matrix(theta * e);
  double warped_error = 0.0, linear_error = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d X = mesh.rest_positions.row(i).transpose() - c;
    const Eigen::Vector3d exact = (R - Eigen::Matrix3d::Identity()) * X;
    warped_error = std::max(warped_error, (warped.segment<3>(3 * i) - exact).norm());
    linear_error = std::max(linear_error, (linear.segment<3>(3 * i) - exact).norm() / std::max(X.norm(), 1e-12));
  }
  std::printf("P1 tets, 90-degree rotation at %d vertices: warped error %.2e, linear mode error %.3f of |X - c|\n", n,
              warped_error, linear_error);
  EXPECT_LT(warped_error, 1e-12);
  EXPECT_GT(linear_error, 0.5);

  std::vector<double> errors;
  for (int k : {1, 2}) {
    const Mesh m = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 4 * k, 2 * k, 2 * k);
    Eigen::MatrixXd bend = Eigen::MatrixXd::Zero(3 * m.num_vertices(), 1);
    for (int i = 0; i < m.num_vertices(); ++i) bend(3 * i + 2, 0) = m.rest_positions(i, 0) * m.rest_positions(i, 0);
    const ModalWarpingOperators b = fem_modal_warping_operators(m, bend);
    double error = 0.0;
    for (int i = 0; i < m.num_vertices(); ++i)
      error = std::max(error, (b.rotation.block<3, 1>(3 * i, 0) - Eigen::Vector3d(0, -m.rest_positions(i, 0), 0)).norm());
    errors.push_back(error);
  }
  std::printf("quadratic field, largest vertex error of the half curl: %.3e (h = 0.5), %.3e (h = 0.25)\n", errors[0],
              errors[1]);
  EXPECT_GT(errors[0], 1e-3);
  EXPECT_LT(errors[1], 0.6 * errors[0]);

  EXPECT_THROW(fem_modal_warping_operators(mesh, modes.topRows(3 * n - 3)), std::invalid_argument);
  EXPECT_THROW(fem_modal_warping_operators(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 2, 2),
                                           Eigen::MatrixXd::Zero(18, 1)),
               std::invalid_argument);
}

TEST(ModalWarping, RayleighDampedStepMatchesTheDampedOscillator) {
  // One mode, omega = 2 pi (1 Hz), alpha = 0.4 / s, beta = 0.01 s: zeta = 0.4 / (4 pi) + 0.01 pi.
  const double lambda = 4.0 * M_PI * M_PI, omega = 2.0 * M_PI;
  const ModalRayleighDamping damping{0.4, 0.01};
  const double zeta = damping.ratio(lambda);
  EXPECT_NEAR(zeta, 0.4 / (2.0 * omega) + 0.01 * omega / 2.0, 1e-15);
  ModalWarpingOperators ops;
  ops.displacement = Eigen::MatrixXd::Ones(3, 1);
  ops.rotation = Eigen::MatrixXd::Zero(3, 1);
  for (double h : {0.001, 0.05, 0.3}) {  // exact at any step, beyond the stability limit of explicit schemes
    WarpedModalSimulator sim(ops, Eigen::VectorXd::Constant(1, lambda), damping, h);
    sim.set_state(Eigen::VectorXd::Ones(1), Eigen::VectorXd::Zero(1));
    const int steps = static_cast<int>(std::round(3.0 / h));
    for (int k = 0; k < steps; ++k) sim.step(Eigen::VectorXd::Zero(1));
    const double t = steps * h, wd = omega * std::sqrt(1.0 - zeta * zeta);
    const double exact = std::exp(-zeta * omega * t) * (std::cos(wd * t) + zeta * omega / wd * std::sin(wd * t));
    EXPECT_NEAR(sim.amplitudes()[0], exact, 1e-11) << h;
  }
  // A constant force settles at f / lambda.
  WarpedModalSimulator sim(ops, Eigen::VectorXd::Constant(1, lambda), damping, 0.05);
  for (int k = 0; k < 2000; ++k) sim.step(Eigen::VectorXd::Constant(1, 2.0));
  EXPECT_NEAR(sim.amplitudes()[0], 2.0 / lambda, 1e-12);
  EXPECT_THROW(WarpedModalSimulator(ops, Eigen::VectorXd::Zero(1), damping, 0.05), std::invalid_argument);
}

// Handles in the warped modal dynamics, on the free 2 x 1 x 1 box (h = 0.5, 45 nodes, linear
// material E = 1000, nu = 0.3, density 1): its 6 rigid modes (lambda = 0) and first 10 elastic
// modes, stiffness k = 1e4 lambda_max for the handles, Rayleigh alpha = 4 / s, beta = 1e-3 s.
struct FreeBox {
  MeshlessSolid solid = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1)), 0.5, 2, 0);
  Eigen::MatrixXd modes;
  Eigen::VectorXd eigenvalues;
  FreeBox() {
    const int n = solid.num_nodes();
    Model model(3 * n);
    model.parameter_layout().add("youngs_modulus", n);
    model.parameter_layout().add("poisson_ratio", n);
    model.add(std::make_unique<MeshlessElasticTerm<3>>(solid.quadrature, make_material<3>(MaterialKind::linear), 0, n));
    ModalAnalysisOptions options;
    options.count = 10;
    const ModalAnalysis m = modal_analysis(model, 3, solid.rest(), uniform_parameters(n, 1000.0, 0.3),
                                           meshless_mass_matrix(*solid.quadrature, 1.0), options);
    EXPECT_EQ(m.rigid_modes.cols(), 6);
    modes.resize(3 * n, 16);
    modes << m.rigid_modes, m.modes;
    eigenvalues.resize(16);
    eigenvalues << Eigen::VectorXd::Zero(6), m.eigenvalues;
  }
  // The nodes with x == end (an end face: 9 nodes).
  std::vector<int> face(double end) const {
    std::vector<int> out;
    for (int a = 0; a < solid.num_nodes(); ++a)
      if (std::abs(solid.sampling.nodes(a, 0) - end) < 1e-9) out.push_back(a);
    return out;
  }
};

// A rotation handle on the end face x = 0, turned by 90 degrees about the z axis through the
// face's centre c, is the only thing acting on the free box: the rigid rotation satisfies it at
// zero elastic energy, so the damped dynamics settle on it, and warping represents it exactly.
// Every node's warped displacement reaches (R - I)(X - c) (reference: the rigid rotation); the
// linear modal displacement is off by 1.15 |X - c| there. Without the handle the rigid modes have
// no stiffness and are refused.
TEST(ModalWarping, RotationHandleTurnsTheFreeWarpedBody) {
  const FreeBox box;
  const int n = box.solid.num_nodes();
  const ModalWarpingOperators ops = modal_warping_operators(*box.solid.mls, box.modes, box.solid.sampling.nodes);
  const ModalRayleighDamping damping{4.0, 1e-3};
  EXPECT_THROW(WarpedModalSimulator(ops, box.eigenvalues, damping, 0.01), std::invalid_argument);
  const Eigen::Vector3d c(0, 0.5, 0.5), w(0, 0, M_PI / 2);
  const Eigen::Matrix3d R = rotation_matrix(w);
  ModalHandle handle;
  handle.points = box.face(0.0);
  ASSERT_EQ(handle.points.size(), 9u);
  handle.displacements.resize(9, 3);
  handle.rotation_weight = 0.0;
  for (std::size_t i = 0; i < 9; ++i) {
    const Eigen::Vector3d X = box.solid.sampling.nodes.row(handle.points[i]).transpose();
    handle.displacements.row(static_cast<Eigen::Index>(i)) = ((R - Eigen::Matrix3d::Identity()) * (X - c)).transpose();
    handle.rotation_weight += (X - c).squaredNorm() / 9.0;
  }
  handle.rotation = w;
  const double k = 1e4 * box.eigenvalues.maxCoeff();
  WarpedModalSimulator sim(ops, box.eigenvalues, damping, 0.01, {handle}, k);
  for (int step = 0; step < 1500; ++step) sim.step(Eigen::VectorXd::Zero(16));
  Eigen::VectorXd warped, linear;
  sim.displacements(warped, true);
  sim.displacements(linear, false);
  double worst = 0.0, linear_worst = 0.0, worst_rotation = 0.0;
  for (int a = 0; a < n; ++a) {
    const Eigen::Vector3d X = box.solid.sampling.nodes.row(a).transpose(), exact = (R - Eigen::Matrix3d::Identity()) * (X - c);
    worst = std::max(worst, (warped.segment<3>(3 * a) - exact).norm());
    if ((X - c).norm() > 0.5) linear_worst = std::max(linear_worst, (linear.segment<3>(3 * a) - exact).norm() / (X - c).norm());
    worst_rotation = std::max(worst_rotation, (ops.rotation.middleRows(3 * a, 3) * sim.amplitudes() - w).norm());
  }
  std::printf("rotation handle, 90 degrees: warped nodes off the rigid rotation by %.2e (largest |X - c| = %.2f), "
              "rotation vectors by %.2e; linear modes off by %.3f |X - c|\n",
              worst, std::sqrt(4.0 + 0.5), worst_rotation, linear_worst);
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(worst_rotation, 1e-8);
  EXPECT_GT(linear_worst, 1.0);
}

// Position handles: the centre of the end x = 0 held in place (displacement 0, rotation 0: a
// clamp at a point) and the centre of the end x = 2 dragged by d = (0, 0.4, 0) with a
// position-only handle (its rotation follows the body: W at the current rotation each step).
// Nine rows on 16 modes can be met: the handled points reach their targets to within the
// penalty's share, 1e-3 |d| (the elastic stiffness over k = 1e4 lambda_max). Holding the whole
// end faces (9 nodes each, 57 rows) asks more than 16 modes can give: the targets are then met
// in the least-squares sense of the modal subspace (measured and printed). Moving the handle
// back returns the box to rest.
TEST(ModalWarping, PositionHandlesMoveTheirNodesToTheTargets) {
  const FreeBox box;
  const ModalWarpingOperators ops = modal_warping_operators(*box.solid.mls, box.modes, box.solid.sampling.nodes);
  int left = -1, right = -1;
  for (int a = 0; a < box.solid.num_nodes(); ++a) {
    const Eigen::Vector3d X = box.solid.sampling.nodes.row(a).transpose();
    if ((X - Eigen::Vector3d(0, 0.5, 0.5)).norm() < 1e-9) left = a;
    if ((X - Eigen::Vector3d(2, 0.5, 0.5)).norm() < 1e-9) right = a;
  }
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  const Eigen::Vector3d d(0, 0.4, 0);
  const double k = 1e4 * box.eigenvalues.maxCoeff();
  const ModalRayleighDamping damping{4.0, 1e-3};
  for (const bool faces : {false, true}) {
    ModalHandle clamp, drag;
    clamp.points = faces ? box.face(0.0) : std::vector<int>{left};
    clamp.displacements = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(clamp.points.size()), 3);
    clamp.rotation = Eigen::Vector3d::Zero();
    clamp.rotation_weight = 0.25;
    drag.points = faces ? box.face(2.0) : std::vector<int>{right};
    drag.displacements = d.transpose().replicate(static_cast<Eigen::Index>(drag.points.size()), 1);
    WarpedModalSimulator sim(ops, box.eigenvalues, damping, 0.01, {clamp, drag}, k);
    for (int step = 0; step < 1500; ++step) sim.step(Eigen::VectorXd::Zero(16));
    Eigen::VectorXd u;
    sim.displacements(u, true);
    double drag_error = 0.0, clamp_error = 0.0;
    for (int a : drag.points) drag_error = std::max(drag_error, (u.segment<3>(3 * a) - d).norm());
    for (int a : clamp.points) clamp_error = std::max(clamp_error, u.segment<3>(3 * a).norm());
    const double clamp_rotation = (ops.rotation.middleRows(3 * left, 3) * sim.amplitudes()).norm();
    const double tip_rotation = (ops.rotation.middleRows(3 * right, 3) * sim.amplitudes()).norm();
    std::printf("position handles (%s): dragged off its target by %.2e (|d| = 0.4), held by %.2e, held rotation "
                "%.2e rad; the dragged end turned by %.3f rad\n",
                faces ? "whole end faces" : "face centres", drag_error, clamp_error, clamp_rotation, tip_rotation);
    if (faces) {
      EXPECT_LT(drag_error, 0.1 * d.norm());
      continue;
    }
    EXPECT_LT(drag_error, 1e-3 * d.norm());
    EXPECT_LT(clamp_error, 1e-3 * d.norm());
    EXPECT_LT(clamp_rotation, 1e-3);
    EXPECT_GT(tip_rotation, 0.2);  // a bent box: the dragged end turns, and the handle follows it
    sim.move_handle(1, Eigen::MatrixXd::Zero(1, 3), std::nullopt);
    for (int step = 0; step < 1500; ++step) sim.step(Eigen::VectorXd::Zero(16));
    sim.displacements(u, true);
    EXPECT_LT(u.cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_THROW(sim.move_handle(1, Eigen::MatrixXd::Zero(1, 3), Eigen::Vector3d::Zero()), std::invalid_argument);
  }
}

}  // namespace
}  // namespace tailor::modal_warping_test
