#pragma once
// The distance between two tori (docs/tori.md).
//
// A solid torus is the set of points within r of its core circle, so the distance between two
// disjoint solid tori is the distance between their core circles minus both tube radii:
//   d = D - r_a - r_b,   D^2 = min_{theta_a, theta_b} f,   f = |c_a(theta_a) - c_b(theta_b)|^2,
// (d <= 0: the tori overlap). D is found by a small minimization over the two core angles u:
// f(theta_a, theta_b(theta_a)) sampled at `samples` angles of a (the best theta_b of a point is
// closed-form: the projection onto b's plane), and Newton on both angles from the lowest local
// minima of the samples; the smallest converged value is D^2.
//
// Derivatives by the implicit function theorem: with y the other variables (T_a, w_a, T_b, w_b,
// R_a, R_b) and f_u = 0 at the minimizer,
//   dD^2/dy = f_y,   d2D^2/dy2 = f_yy - f_yu f_uu^{-1} f_uy,
// exact where the minimizer is unique and non-degenerate (f_uu positive definite); f and its
// first and second derivatives in (u, y) come from Dual2 (forward/core/dual2.hpp) through the
// Rodrigues rotation's exact derivatives. Coaxial or otherwise degenerate pairs (a circle of
// minimizers) have no such derivatives: distance() reports them (`degenerate`).
//
// This holds for circular tubes only. When either torus is elliptic (r1 != r, torus.hpp),
// torus_distance() hands the pair to elliptic_torus_distance (elliptic_distance.hpp): a
// minimization over both surfaces' four parameters, overlap by the tubes' implicit functions.
#include <Eigen/Core>

#include "forward/tori/torus.hpp"

namespace tailor::tori {

// The pose and shape of one torus.
struct TorusPose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // T
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();  // w
  TorusShape shape;
};

// Variables of the derivatives, in this order (16):
//   0-2 T_a, 3-5 w_a, 6-8 T_b, 9-11 w_b, 12 R_a, 13 r_a, 14 R_b, 15 r_b.
constexpr int kPairVariables = 16;
using PairGradient = Eigen::Matrix<double, kPairVariables, 1>;
using PairHessian = Eigen::Matrix<double, kPairVariables, kPairVariables>;

// For an elliptic torus the r variable is its radial semi-axis r with r1 held; for a circular
// one (r1 = r) r moves both semi-axes (the circular family).
struct TorusDistance {
  double distance = 0.0;                // d = D - r_a - r_b [length] (elliptic: the surface distance)
  double core_distance = 0.0;           // D (elliptic: NaN, no such reduction)
  double theta_a = 0.0, theta_b = 0.0;  // the minimizing core angles (elliptic: the surface's u)
  double tube_a = 0.0, tube_b = 0.0;    // elliptic: the minimizing tube angles v
  bool degenerate = false;              // f_uu not positive definite at the minimizer (no derivatives)
  // Elliptic: the solids overlap (found by the tubes' implicit functions); distance is then a
  // negative penetration estimate and there are no derivatives (degenerate is set too).
  bool overlapping = false;
  PairGradient gradient = PairGradient::Zero();  // dd/dvariables (when requested)
  PairHessian hessian = PairHessian::Zero();     // d2d/dvariables2 (when requested)
  // Elliptic: dd/dr1_a, dd/dr1_b (when requested; zero for a circular torus of the pair, whose
  // r1 moves with r).
  Eigen::Vector2d axial_gradient = Eigen::Vector2d::Zero();
};

struct DistanceOptions {
  int samples = 32;    // angles of a sampled for the starts
  int max_starts = 4;  // Newton runs from the lowest local minima of the samples
  int max_iterations = 50;
  // Elliptic pairs: each surface sampled at surface_samples x surface_samples / 2 (u, v) points;
  // Newton from the pairs of the surface_starts lowest local minima over a's samples.
  int surface_samples = 16;
  int surface_starts = 6;
  // false drops the -f_yu f_uu^-1 f_uy term (a deliberately wrong Hessian: only for the test
  // that shows the derivative check catches it).
  bool implicit_correction = true;
};

// The distance between tori a and b; with `derivatives` its gradient and Hessian in the 16
// variables (zero when degenerate).
TorusDistance torus_distance(const TorusPose& a, const TorusPose& b, bool derivatives,
                             const DistanceOptions& options = {});

// A point of a torus's core circle in the world.
Eigen::Vector3d core_point(const TorusPose& pose, double theta);

}  // namespace tailor::tori
