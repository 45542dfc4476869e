// Modal warping (Choi & Ko 2005) on meshless modes: W(w) against quadrature of its definition,
// a 90-degree rigid rotation represented exactly by the warped linearized rotation where the
// linear mode distorts by a measured amount, and the Rayleigh-damped modal step against the
// closed-form damped oscillator (Chopra, Dynamics of Structures, eq. 2.2.4).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "forward/meshless/modal_warping.hpp"
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

}  // namespace
}  // namespace tailor::modal_warping_test
