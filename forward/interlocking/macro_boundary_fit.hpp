#pragma once
// A smooth fit of a measured strain-space boundary for the macro-scale sheet (docs/interlocking.md,
// "Macro-scale model").
//
// The native sweep (strain_boundary.hpp, principal loading) gives limit points (e_xx, e_yy) of the
// principal strains e = lambda - 1 (F = diag(lambda_1, lambda_2)). The macro model treats the
// admissible set as a function of the principal strains only (e_1, e_2 unordered: an isotropic set,
// see the docs for what that neglects) and describes it in polar form in the (e_1, e_2) plane,
//   rho <= r(c),   rho = |(e_1, e_2)|,   c = cos(phi) = (e_1 + e_2) / (sqrt(2) rho),
// phi the angle from the equibiaxial ray (1, 1). Swapping e_1 and e_2 reflects phi, so r is an even
// Fourier series in phi: r = sum_k a_k cos(k phi) = sum_k a_k T_k(c) (T_k Chebyshev polynomials),
// fitted by linear least squares to the samples (a sample at (e_xx, e_yy) and its mirror
// (e_yy, e_xx) are the same point of this plane). Written in c, r is a polynomial of the strain
// invariants' smooth functions, so it has exact derivatives of every order away from rho = 0.
#include <Eigen/Core>
#include <vector>

namespace tailor::interlocking {

struct BoundaryFit {
  std::vector<double> coefficients;  // a_0 ... a_K of r(c) = sum a_k T_k(c)  [strain]
  int samples = 0;
  double rms_residual = 0.0;  // sqrt(mean (r(c_i) - rho_i)^2) over the samples [strain]
  double max_residual = 0.0;  // max |r(c_i) - rho_i| [strain]
  double min_radius = 0.0;    // smallest r(c) on c in [-1, 1] (checked positive by fit_boundary)

  // r(c) by the Chebyshev recurrence; Scalar may be double or Dual2<N> (exact derivatives).
  template <class Scalar>
  Scalar radius(const Scalar& c) const {
    Scalar t_prev(1.0), t(c);
    Scalar r = Scalar(coefficients[0]);
    if (coefficients.size() > 1) r = r + coefficients[1] * c;
    for (std::size_t k = 2; k < coefficients.size(); ++k) {
      const Scalar t_next = 2.0 * c * t - t_prev;
      r = r + coefficients[k] * t_next;
      t_prev = t;
      t = t_next;
    }
    return r;
  }
  // The limit radius along the principal-strain direction (cos t, sin t) [strain].
  double radius_at_angle(double angle) const;
};

// Least-squares fit of order `order` (>= 0) to limit points (e_xx, e_yy) of principal rays, each
// point the locked principal strains of one direction. Throws std::invalid_argument with fewer
// samples than order + 1 distinct values of c, a sample at the origin, or a fit whose radius is not
// positive on all of [-1, 1] (the admissible set must contain a disc about the rest state).
BoundaryFit fit_boundary(const std::vector<Eigen::Vector2d>& limit_strains, int order);

// The least-squares coefficients c minimising |design c - values| (rows: samples), by the normal
// equations and the compiled-once symmetric eigen-decomposition (pseudo-inverse: directions the
// samples leave free get zero). Shared by the boundary fits of the macro model.
std::vector<double> least_squares(const Eigen::MatrixXd& design, const Eigen::VectorXd& values);

// The margin to the fitted boundary of principal strains e = (e_1, e_2):
//   g = 1 - rho / r(c)  (1 at rest, 0 on the boundary, negative outside) [dimensionless].
double boundary_margin(const BoundaryFit& fit, const Eigen::Vector2d& principal_strains);

}  // namespace tailor::interlocking
