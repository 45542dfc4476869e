// The macro-scale interlocking sheet's membrane with its boundary barrier (see macro_sheet_term.hpp).
#include "forward/interlocking/macro_sheet_term.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/core/dual2.hpp"
#include "forward/core/psd_projection.hpp"
#include "forward/fem/element_loop.hpp"

namespace tailor::interlocking {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The Biot strain E = U - I from C = F^T F (C11, C22, C12), by the closed form of the 2 x 2 square
// root: U = (C + sqrt(det C) I) / sqrt(tr C + 2 sqrt(det C)). Returns (E_xx, E_yy, E_xy) and rho = |E|.
template <class Scalar>
void biot_strain(const Scalar& C11, const Scalar& C22, const Scalar& C12, Scalar& exx, Scalar& eyy, Scalar& exy,
                 Scalar& rho2) {
  const Scalar root = sqrt(C11 * C22 - C12 * C12);
  const Scalar trace_u = sqrt(C11 + C22 + 2.0 * root);  // lambda_1 + lambda_2
  exx = (C11 + root) / trace_u - 1.0;
  eyy = (C22 + root) / trace_u - 1.0;
  exy = C12 / trace_u;
  rho2 = exx * exx + eyy * eyy + 2.0 * exy * exy;
}

// psi(C11, C22, C12) of the header [energy / area]; `barrier` adds kappa b(g) (the caller has checked
// 0 < g < g_hat, so rho > 0 there).
template <class Scalar>
Scalar sheet_density(const Scalar& C11, const Scalar& C22, const Scalar& C12, const MacroStrainSet& set,
                     const MacroSheetMaterial& m, bool barrier) {
  Scalar exx, eyy, exy, rho2;
  biot_strain(C11, C22, C12, exx, eyy, exy, rho2);
  Scalar psi = 0.5 * m.stiffness * rho2;
  if (barrier) {
    const Scalar rho = sqrt(rho2);
    const Scalar u = (exx + eyy) / (std::sqrt(2.0) * rho), v = (exx - eyy) / (std::sqrt(2.0) * rho),
                 w = std::sqrt(2.0) * exy / rho;
    const Scalar g = 1.0 - rho / set.radius(u, v, w);
    const Scalar d = g - m.barrier_activation;
    psi = psi - m.barrier_stiffness * d * d * log(g / m.barrier_activation);
  }
  return psi;
}

// The columns f1, f2 of F for element k at full state x.
void columns(const SheetTriangles& t, const Vector& x, int k, Eigen::Vector3d& f1, Eigen::Vector3d& f2) {
  f1.setZero();
  f2.setZero();
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d xa = x.segment<3>(3 * t.vertices[static_cast<std::size_t>(k)][a]);
    f1 += t.gradients[static_cast<std::size_t>(k)](a, 0) * xa;
    f2 += t.gradients[static_cast<std::size_t>(k)](a, 1) * xa;
  }
}

// The margin g from C = F^T F: 1 at rest, 0 on the boundary; -infinity for a degenerate element.
double margin_of(double C11, double C22, double C12, const MacroStrainSet& set) {
  if (!(C11 * C22 - C12 * C12 > 0.0)) return -kInfinity;
  double exx = 0.0, eyy = 0.0, exy = 0.0, rho2 = 0.0;
  biot_strain(C11, C22, C12, exx, eyy, exy, rho2);
  if (!(rho2 > 1e-24)) return 1.0;
  return set.margin(Eigen::Vector3d(exx, eyy, exy));
}

}  // namespace

MacroSheetTerm::MacroSheetTerm(const Mesh& flat, MacroStrainSet set, MacroSheetMaterial material)
    : set_(std::move(set)), material_(material) {
  if (flat.dim() != 2 || flat.elements.cols() != 3)
    throw std::invalid_argument("MacroSheetTerm: the rest sheet must be a 2D triangle mesh");
  if ((set_.anisotropic ? set_.oriented.coefficients : set_.isotropic.coefficients).empty()) throw std::invalid_argument("MacroSheetTerm: the boundary fit is empty");
  if (!(material_.stiffness >= 0.0) || !(material_.barrier_stiffness > 0.0) ||
      !(material_.barrier_activation > 0.0 && material_.barrier_activation < 1.0))
    throw std::invalid_argument(
        "MacroSheetTerm: needs stiffness >= 0, barrier_stiffness > 0, 0 < barrier_activation < 1");
  for (int k = 0; k < flat.num_elements(); ++k) {
    Eigen::Matrix<int, 3, 1> v = flat.elements.row(k).transpose();
    Eigen::Matrix2d Dm;
    Dm.col(0) = (flat.rest_positions.row(v[1]) - flat.rest_positions.row(v[0])).transpose();
    Dm.col(1) = (flat.rest_positions.row(v[2]) - flat.rest_positions.row(v[0])).transpose();
    const double det = Dm.determinant();
    if (!(det > 1e-14 * Dm.squaredNorm()))
      throw std::invalid_argument("MacroSheetTerm: triangle " + std::to_string(k) +
                                  " is degenerate or clockwise");
    const Eigen::Matrix2d inv = Dm.inverse();
    Eigen::Matrix<double, 3, 2> G;
    G.row(1) = inv.row(0);
    G.row(2) = inv.row(1);
    G.row(0) = -inv.row(0) - inv.row(1);
    triangles_.vertices.push_back(v);
    triangles_.gradients.push_back(G);
    triangles_.areas.push_back(0.5 * det);
  }
}

void MacroSheetTerm::hessian_pattern(HessianPattern& pattern) const {
  for (int k = 0; k < triangles_.size(); ++k)
    for (int r = 0; r < 9; ++r)
      for (int c = 0; c < 9; ++c)
        pattern.push_back({3 * triangles_.vertices[static_cast<std::size_t>(k)][r / 3] + r % 3,
                           3 * triangles_.vertices[static_cast<std::size_t>(k)][c / 3] + c % 3});
}

void MacroSheetTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  evaluate_elements<3>(triangles_, request, [&](int k, ElementOutput<3, 3>& out) {
    Eigen::Vector3d f1, f2;
    columns(triangles_, x, k, f1, f2);
    const double C11 = f1.squaredNorm(), C22 = f2.squaredNorm(), C12 = f1.dot(f2);
    const double area = triangles_.areas[static_cast<std::size_t>(k)];
    const double g = margin_of(C11, C22, C12, set_);
    if (out.want_gradient) out.gradient().setZero();
    if (out.want_hessian) out.hessian().setZero();
    if (!(g > 0.0)) {  // outside the admissible set (or degenerate): the line search backs off
      out.energy = kInfinity;
      return;
    }
    const bool barrier = g < material_.barrier_activation;
    if (!out.want_gradient && !out.want_hessian) {
      out.energy = area * sheet_density(C11, C22, C12, set_, material_, barrier);
      return;
    }
    const Dual2<3> psi = sheet_density(Dual2<3>::variable(C11, 0), Dual2<3>::variable(C22, 1),
                                       Dual2<3>::variable(C12, 2), set_, material_, barrier);
    out.energy = area * psi.v;
    // d psi / d f, f = (f1; f2): C11 = f1.f1, C22 = f2.f2, C12 = f1.f2, in plain loops: the chain to
    // the element's DOFs, x_a -> f_j with weight G(a, j), is a sum, not a product of fixed-size
    // matrices (those cost compile time in every build).
    double dC[3][6], Hf[6][6];
    for (int d = 0; d < 3; ++d) {
      dC[0][d] = 2.0 * f1[d];
      dC[0][3 + d] = 0.0;
      dC[1][d] = 0.0;
      dC[1][3 + d] = 2.0 * f2[d];
      dC[2][d] = f2[d];
      dC[2][3 + d] = f1[d];
    }
    double df[6];
    for (int r = 0; r < 6; ++r) df[r] = psi.g[0] * dC[0][r] + psi.g[1] * dC[1][r] + psi.g[2] * dC[2][r];
    const Eigen::Matrix<double, 3, 2>& G = triangles_.gradients[static_cast<std::size_t>(k)];
    if (out.want_gradient) {
      auto gl = out.gradient();
      for (int n = 0; n < 3; ++n)
        for (int d = 0; d < 3; ++d) gl(d, n) = area * (G(n, 0) * df[d] + G(n, 1) * df[3 + d]);
    }
    if (out.want_hessian) {
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) {
          double v = 0.0;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) v += psi.h(i, j) * dC[i][r] * dC[j][c];
          // The second derivatives of C: 2 I on (f1, f1) and (f2, f2), I on (f1, f2) and (f2, f1).
          if (r % 3 == c % 3) v += (r / 3 == c / 3) ? 2.0 * psi.g[r / 3] : psi.g[2];
          Hf[r][c] = v;
        }
      Eigen::Matrix<double, 9, 9> H;
      for (int na = 0; na < 3; ++na)
        for (int nb = 0; nb < 3; ++nb)
          for (int d = 0; d < 3; ++d)
            for (int e = 0; e < 3; ++e) {
              double v = 0.0;
              for (int j = 0; j < 2; ++j)
                for (int l = 0; l < 2; ++l) v += G(na, j) * G(nb, l) * Hf[3 * j + d][3 * l + e];
              H(3 * na + d, 3 * nb + e) = area * v;
            }
      if (out.hessian_mode == HessianMode::projected) project_psd(H);
      out.hessian() = H;
    }
  });
}

double MacroSheetTerm::margin(const Vector& x, int k) const {
  Eigen::Vector3d f1, f2;
  columns(triangles_, x, k, f1, f2);
  return margin_of(f1.squaredNorm(), f2.squaredNorm(), f1.dot(f2), set_);
}

double MacroSheetTerm::max_step(const Vector& x, const Vector& dx) const {
  constexpr int kSamples = 16;
  double t_max = 1.0;
  for (int k = 0; k < triangles_.size(); ++k) {
    const double g0 = margin(x, k);
    if (!(g0 > 0.0)) return 0.0;
    const double floor = 0.2 * g0;
    // F is linear in x: F(t) = F(x) + t F(dx), from the element's columns of both.
    Eigen::Vector3d f1, f2, d1, d2;
    columns(triangles_, x, k, f1, f2);
    columns(triangles_, dx, k, d1, d2);
    const auto below = [&](double t) {
      const Eigen::Vector3d a = f1 + t * d1, b = f2 + t * d2;
      return !(margin_of(a.squaredNorm(), b.squaredNorm(), a.dot(b), set_) > floor);
    };
    double t_ok = 0.0;
    for (int i = 1; i <= kSamples; ++i) {
      const double t = t_max * i / kSamples;
      if (!below(t)) {
        t_ok = t;
        continue;
      }
      double lo = t_ok, hi = t;
      for (int it = 0; it < 30; ++it) {
        const double mid = 0.5 * (lo + hi);
        (below(mid) ? hi : lo) = mid;
      }
      t_max = lo;
      break;
    }
  }
  return t_max;
}

Eigen::MatrixXd MacroSheetTerm::principal_strains(const Vector& x) const {
  Eigen::MatrixXd e(triangles_.size(), 2);
  for (int k = 0; k < triangles_.size(); ++k) {
    Eigen::Vector3d f1, f2;
    columns(triangles_, x, k, f1, f2);
    const double f12 = f1.dot(f2);
    const double I1 = f1.squaredNorm() + f2.squaredNorm();
    const double I2 = std::max(0.0, f1.squaredNorm() * f2.squaredNorm() - f12 * f12);
    const double sum = std::sqrt(I1 + 2.0 * std::sqrt(I2));                  // lambda_1 + lambda_2
    const double diff = std::sqrt(std::max(0.0, I1 - 2.0 * std::sqrt(I2)));  // lambda_1 - lambda_2
    e(k, 0) = 0.5 * (sum + diff) - 1.0;
    e(k, 1) = 0.5 * (sum - diff) - 1.0;
  }
  return e;
}

Eigen::VectorXd MacroSheetTerm::margins(const Vector& x) const {
  Eigen::VectorXd g(triangles_.size());
  for (int k = 0; k < triangles_.size(); ++k) g[k] = margin(x, k);
  return g;
}

Eigen::MatrixXd MacroSheetTerm::strains(const Vector& x) const {
  Eigen::MatrixXd e(triangles_.size(), 3);
  for (int k = 0; k < triangles_.size(); ++k) {
    Eigen::Vector3d f1, f2;
    columns(triangles_, x, k, f1, f2);
    double exx = 0.0, eyy = 0.0, exy = 0.0, rho2 = 0.0;
    biot_strain(f1.squaredNorm(), f2.squaredNorm(), f1.dot(f2), exx, eyy, exy, rho2);
    e.row(k) << exx, eyy, exy;
  }
  return e;
}

}  // namespace tailor::interlocking
