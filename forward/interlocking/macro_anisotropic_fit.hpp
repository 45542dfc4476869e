#pragma once
// The anisotropic admissible set of the macro-scale sheet (docs/interlocking.md, "Macro-scale
// model"): a radial function over the unit sphere of in-plane strain directions, fitted to native
// limits along directions of the 3D strain space (e_xx, e_yy, e_xy).
//
// A strain E (symmetric 2 x 2, Biot: E = U - I, U the right stretch; on a native path F = I + s G
// with G symmetric, E = s G) has the Frobenius size rho = |E| = sqrt(e_xx^2 + e_yy^2 + 2 e_xy^2)
// and the direction n = (u, v, w) on the unit sphere,
//   u = (e_xx + e_yy) / (sqrt(2) rho)   (equibiaxial part; the isotropic fit's c),
//   v = (e_xx - e_yy) / (sqrt(2) rho),  w = sqrt(2) e_xy / rho   (deviatoric part).
// With u the pole, (v, w) = sin(phi) (cos beta, sin beta), and a rotation of the material by alpha
// turns beta by 2 alpha: the set is admissible where rho <= r(n),
//   r(n) = sum_{l <= L} sum_{|m| <= min(l, M)} a_lm Y_lm(n)
// (real spherical harmonics, written as polynomials in u, v, w: exact derivatives of every order).
// m = 0 terms are the isotropic set (a function of u alone, the span of the principal-strain fit);
// m != 0 terms carry the dependence on the strain's orientation (a square net: even m only).
// Fitted by linear least squares (macro_boundary_fit.hpp's least_squares), residuals reported;
// material symmetries add the mirrored images of each sample. The native sweeps over the sphere of
// strain directions that give the samples: macro_strain_sweep.hpp.
#include <Eigen/Core>
#include <cmath>
#include <utility>
#include <vector>

#include "forward/interlocking/macro_boundary_fit.hpp"

namespace tailor::interlocking {

// Material symmetries of the set, used to mirror the samples.
struct StrainSetSymmetry {
  bool reflect = false;  // e_xy -> -e_xy (a mirror about the x axis): w -> -w
  bool swap = false;     // e_xx <-> e_yy (a mirror about the diagonal): v -> -v
};

struct AnisotropicBoundaryFit {
  int degree = 0;                    // L
  int max_order = 0;                 // M: |m| <= min(l, M)
  std::vector<double> coefficients;  // a_lm in basis order (m = 0..M, l = m..L; m > 0: cos, sin)
  int samples = 0;                   // native samples (before mirroring)
  double rms_residual = 0.0;         // sqrt(mean (r(n_i) - rho_i)^2) over the samples [strain]
  double max_residual = 0.0;         // max |r(n_i) - rho_i| [strain]
  double min_radius = 0.0;           // smallest r over a 2 degree grid of the sphere (checked > 0)

  // r(u, v, w) for a unit (u, v, w); Scalar double or Dual2<N> (exact derivatives).
  template <class Scalar>
  Scalar radius(const Scalar& u, const Scalar& v, const Scalar& w) const;
  // The limit along the direction of strain e = (e_xx, e_yy, e_xy) (not zero) [strain].
  double radius_along(const Eigen::Vector3d& strain) const;
};

// The least-squares fit of degree L, orders |m| <= M (M <= L), to limit strains (e_xx, e_yy,
// e_xy), each the locked strain of one native path through the origin. Throws
// std::invalid_argument for a bad degree, a sample at the origin, too few distinct directions
// for the basis ((L+1)^2 at M = L), or a fit whose radius is not positive on the whole sphere.
AnisotropicBoundaryFit fit_anisotropic_boundary(const std::vector<Eigen::Vector3d>& limit_strains, int degree,
                                                int max_order, const StrainSetSymmetry& symmetry = {});

// The admissible set the sheet uses: the isotropic principal-strain fit or the anisotropic one.
struct MacroStrainSet {
  bool anisotropic = false;
  BoundaryFit isotropic;
  AnisotropicBoundaryFit oriented;
  MacroStrainSet() = default;
  MacroStrainSet(BoundaryFit fit) : isotropic(std::move(fit)) {}  // NOLINT: either fit is a set
  MacroStrainSet(AnisotropicBoundaryFit fit) : anisotropic(true), oriented(std::move(fit)) {}  // NOLINT
  template <class Scalar>
  Scalar radius(const Scalar& u, const Scalar& v, const Scalar& w) const {
    return anisotropic ? oriented.radius(u, v, w) : isotropic.radius(u);
  }
  double radius_along(const Eigen::Vector3d& strain) const;  // [strain]
  // g = 1 - rho / r(n) of a strain (e_xx, e_yy, e_xy): 1 at rest, 0 on the boundary.
  double margin(const Eigen::Vector3d& strain) const;
};

template <class Scalar>
Scalar AnisotropicBoundaryFit::radius(const Scalar& u, const Scalar& v, const Scalar& w) const {
  // Real spherical harmonics with pole u: Y_lm = N_lm Pbar_lm(u) {C_m, S_m}(v, w), Pbar_lm the
  // associated Legendre function divided by (1 - u^2)^(m/2) (a polynomial), C_m + i S_m =
  // (v + i w)^m, N_lm the orthonormal factor. The recurrences are those of the associated Legendre
  // functions (Abramowitz & Stegun 8.5.3).
  Scalar r(0.0);
  Scalar cm(1.0), sm(0.0);  // C_m, S_m
  std::size_t index = 0;
  double diagonal = 1.0;  // (2m - 1)!!
  for (int m = 0; m <= max_order; ++m) {
    if (m > 0) {
      const Scalar c_next = v * cm - w * sm;
      sm = v * sm + w * cm;
      cm = c_next;
      diagonal *= 2.0 * m - 1.0;
    }
    Scalar p_prev(0.0), p(diagonal);  // Pbar_(l-1), Pbar_l at l = m
    double factorial_ratio = 1.0;     // (l - m)! / (l + m)! at l = m: 1 / (2m)!
    for (int k = 1; k <= 2 * m; ++k) factorial_ratio /= k;
    for (int l = m; l <= degree; ++l) {
      if (l > m) {
        const Scalar p_next = ((2.0 * l - 1.0) * u * p - (l + m - 1.0) * p_prev) / static_cast<double>(l - m);
        p_prev = p;
        p = p_next;
        factorial_ratio *= static_cast<double>(l - m) / static_cast<double>(l + m);
      }
      const double norm = std::sqrt((2.0 * l + 1.0) / (4.0 * M_PI) * factorial_ratio) * (m > 0 ? std::sqrt(2.0) : 1.0);
      if (m == 0) {
        r = r + coefficients[index++] * norm * p;
      } else {
        r = r + coefficients[index++] * norm * (p * cm);
        r = r + coefficients[index++] * norm * (p * sm);
      }
    }
  }
  return r;
}

}  // namespace tailor::interlocking
