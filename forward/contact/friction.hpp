#pragma once
// Smoothed, lagged friction of IPC (Li et al. 2020, section 5), per contact pair, on the 12
// stencil coordinates (point k, axis j -> 3k + j).
//
// Lagged at a configuration x_lag (the start of the time step, or a previous solution):
//   - the closest points of the pair's classified distance (distance.hpp), as a combination
//     r = B x of the stencil points (weights +1 .. on the first primitive, - .. on the second:
//     r is the vector between the closest points, B is 3 x 12);
//   - the normal n = r / |r| and an orthonormal tangent basis P = [t1 t2] (3 x 2) of the plane
//     orthogonal to n; Gamma = P^T B (2 x 12) maps stencil displacements to the relative
//     tangential displacement of the closest points;
//   - the normal force magnitude lambda = -d(kappa m b)/dd = kappa m(c) |b'(d^2)| 2 d (b the
//     barrier on squared distances, m the edge-edge mollifier, 1 for point-triangle pairs).
// With these fixed, the friction potential of the pair at stencil coordinates x is
//   D(x) = mu lambda f0(|u|),   u = Gamma (x - x_start)   [energy],
// x_start the stencil at the start of the time step and f0 the C1 smoothing of |u| with the
// threshold eps = eps_v h (a tangential speed eps_v over the step h):
//   f1(y) = 2 y / eps - y^2 / eps^2 for y < eps, 1 otherwise   (f1 = f0', f0(0) = eps / 3),
//   f0(y) = y^3 / (-3 eps^2) + y^2 / eps + eps / 3 for y < eps, y otherwise.
// Its gradient is the friction force mu lambda f1(|u|) u / |u| (magnitude mu lambda once
// sliding faster than eps_v: Coulomb's law), and its Hessian in u,
//   mu lambda [ f1(y) / y I + (d/dy (f1(y) / y)) u u^T / y ],
// is positive semidefinite (eigenvalues f1(y) / y and f1'(y) >= 0).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "forward/contact/contact_potential.hpp"

namespace tailor::contact {

struct FrictionOptions {
  double coefficient = 0.0;          // mu (0: no friction)
  double velocity_threshold = 1e-3;  // eps_v [length / time]: below it the friction force is smoothed
};

// One contact pair's lagged friction data.
struct FrictionPair {
  PairKind kind = PairKind::point_triangle;
  std::array<int, 4> vertices{};         // the stencil (surface vertices)
  Eigen::Matrix<double, 2, 12> tangent;  // Gamma = P^T B
  double normal_force = 0.0;             // lambda [force]
  Eigen::Matrix<double, 12, 1> start;    // stencil coordinates at the start of the step
};

// Gamma, the normal and the closest-point weights of a classified pair at `points` (exposed for
// tests). `weights[k]` multiplies stencil point k in r = sum_k weights[k] x_k.
struct PairTangent {
  std::array<double, 4> weights{};
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 2, 12> tangent = Eigen::Matrix<double, 2, 12>::Zero();
};
PairTangent pair_tangent(const ClassifiedDistance& distance, const std::array<Point, 4>& points);
// The orthonormal tangent basis P = [t1 t2] of the plane orthogonal to the unit normal n that
// pair_tangent uses (t1 from the axis least aligned with n, t2 = n x t1).
Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& normal);

// The smoothing functions of |u| (see above), for y >= 0 and threshold eps > 0.
double friction_f0(double y, double eps);
double friction_f1(double y, double eps);

// The friction pairs of every active barrier pair at x_lag (normal forces with the potential's
// stiffness), with displacements measured from x_start.
std::vector<FrictionPair> lag_friction_pairs(const ContactPotential& potential, const Positions& x_lag,
                                             const Positions& x_start);

// D of one pair at stencil coordinates x (and with `derivatives`, its gradient and Hessian in the
// 12 coordinates), for coefficient mu and threshold eps [length].
struct FrictionDerivatives {
  double value = 0.0;
  Eigen::Matrix<double, 12, 1> gradient = Eigen::Matrix<double, 12, 1>::Zero();
  Eigen::Matrix<double, 12, 12> hessian = Eigen::Matrix<double, 12, 12>::Zero();
  double slip = 0.0;  // |u| [length]
};
FrictionDerivatives friction_pair_potential(const FrictionPair& pair, const Eigen::Matrix<double, 12, 1>& x,
                                            double mu, double eps, bool derivatives);

}  // namespace tailor::contact
