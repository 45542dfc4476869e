// The augmented lock-up system and its implicit-function-theorem derivative (see
// limit_sensitivity.hpp).
#include "forward/interlocking/limit_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/tori/torus_distance.hpp"

namespace tailor::interlocking {
namespace {

// x = x0(F(s)) + S y; dx/ds at s (periodic cells: the image translations' rows G L shift, the
// same at every s; bending patches: the rim poses' derivative, which depends on s).
Vector path_state_derivative(const PeriodicRigidCell& cell, const LoadPath& path, double s) {
  return cell.offset_derivative(path.deformation(s), path.direction);
}

// The critical pair's distance with its gradient in x (full) and in the 16 pair variables.
struct CriticalDistance {
  double distance = 0.0;
  Vector gradient_x;
  tori::PairGradient pair_gradient;
  bool degenerate = false;
};
CriticalDistance critical_distance(const PeriodicRigidCell& cell, const Vector& x, int a, int b) {
  const Vector p = cell.radii_parameters();
  const tori::TorusDistance d =
      tori::torus_distance(cell.contact().pose(a, x, p), cell.contact().pose(b, x, p), true,
                           cell.contact().options().distance);
  CriticalDistance out;
  out.distance = d.distance;
  out.degenerate = d.degenerate;
  out.pair_gradient = d.gradient;
  out.gradient_x = Vector::Zero(x.size());
  out.gradient_x.segment<6>(6 * a) = d.gradient.segment<6>(0);
  out.gradient_x.segment<6>(6 * b) = d.gradient.segment<6>(6);
  return out;
}

// The pseudo-inverse of a symmetric matrix (eigenvalues below 1e-10 of the largest dropped), by
// the eigen-decomposition compiled once in forward/core (no solver instantiated here).
struct PseudoInverse {
  explicit PseudoInverse(const Matrix& H) {
    Vector values;
    symmetric_eigen<Eigen::Dynamic>(H, values, vectors);
    const double cut = 1e-10 * values.cwiseAbs().maxCoeff();
    inverse = Vector::Zero(values.size());
    for (int i = 0; i < values.size(); ++i)
      if (std::abs(values[i]) > cut) inverse[i] = 1.0 / values[i];
  }
  Vector solve(const Vector& b) const { return vectors * (inverse.asDiagonal() * (vectors.transpose() * b)); }
  Matrix vectors;
  Vector inverse;
};

}  // namespace

RefineResult refine_limit(const PeriodicRigidCell& cell, const LoadPath& path, double target_distance, int a, int b,
                          const Vector& y_start, double s_start, int max_iterations) {
  RefineResult r;
  r.y = y_start;
  r.strain = s_start;
  if (cell.mesh_contact()) {  // a mesh pair's distance is a minimum over primitive pairs: not smooth
    r.message = "mesh cells are not refined (the bisection's bracket is the limit's accuracy)";
    return r;
  }
  const SparseMatrix& S = cell.basis();
  const double d_hat = cell.activation_distance();
  for (int it = 0;; ++it) {
    r.iterations = it;
    const Vector x = cell.full_state(r.y, path.deformation(r.strain));
    const Vector xs = path_state_derivative(cell, path, r.strain);
    const ReducedContact c = reduced_contact(cell, x, true, HessianMode::exact);
    const CriticalDistance d = critical_distance(cell, x, a, b);
    if (!std::isfinite(c.energy) || d.degenerate) {
      r.message = "the augmented Newton left the admissible set";
      return r;
    }
    r.residual = c.gradient.lpNorm<Eigen::Infinity>();
    r.constraint = std::abs(d.distance - target_distance);
    if (r.residual <= 1e-10 && r.constraint <= 1e-12 * d_hat) {
      r.converged = true;
      return r;
    }
    if (it >= max_iterations) {
      r.message = "augmented Newton: " + std::to_string(it) + " iterations, residual " + std::to_string(r.residual) +
                  ", constraint " + std::to_string(r.constraint);
      // Round-off: accept states whose residual has stalled far below the force scale.
      r.converged = r.residual <= 1e-7 && r.constraint <= 1e-9 * d_hat;
      return r;
    }
    const PseudoInverse Hinv(c.hessian);
    const Vector fs = S.transpose() * (c.full_hessian * xs);
    const Vector cy = S.transpose() * d.gradient_x;
    const double cs = d.gradient_x.dot(xs);
    const Vector lambda = Hinv.solve(cy);
    const double residual_c = d.distance - target_distance;
    const double ds = (-residual_c + lambda.dot(c.gradient)) / (cs - lambda.dot(fs));
    const Vector dy = -Hinv.solve(c.gradient + fs * ds);
    double alpha = 1.0;
    for (int ls = 0; ls < 30; ++ls, alpha *= 0.5) {
      const Vector xt = cell.full_state(r.y + alpha * dy, path.deformation(r.strain + alpha * ds));
      if (smallest_distance(cell, xt, d_hat) > 0.0) break;
    }
    r.y += alpha * dy;
    r.strain += alpha * ds;
  }
}

Vector equilibrium_tangent(const PeriodicRigidCell& cell, const LoadPath& path, const Vector& y, double s) {
  const Vector x = cell.full_state(y, path.deformation(s));
  const ReducedContact c = reduced_contact(cell, x, true, HessianMode::exact);
  if (!(c.energy > 0.0) || !std::isfinite(c.energy)) return Vector::Zero(y.size());
  const Vector fs = cell.basis().transpose() * (c.full_hessian * path_state_derivative(cell, path, s));
  return -PseudoInverse(c.hessian).solve(fs);
}

LimitGradient limit_gradient(const PeriodicRigidCell& cell, const LoadPath& path, int a, int b, const Vector& y,
                             double s) {
  if (cell.mesh_contact()) throw std::invalid_argument("limit_gradient: mesh cells have no limit derivatives");
  const SparseMatrix& S = cell.basis();
  const Eigen::Matrix2d F = path.deformation(s);
  const Vector x = cell.full_state(y, F);
  const Vector p = cell.radii_parameters();
  const ReducedContact c = reduced_contact(cell, x, true, HessianMode::exact);
  const CriticalDistance d = critical_distance(cell, x, a, b);
  const PseudoInverse Hinv(c.hessian);
  const Vector xs = path_state_derivative(cell, path, s);
  const Vector fs = S.transpose() * (c.full_hessian * xs);
  const Vector cy = S.transpose() * d.gradient_x;
  const Vector lambda = Hinv.solve(cy);
  LimitGradient g;
  g.denominator = d.gradient_x.dot(xs) - lambda.dot(fs);

  // Radii: f_p = S^T M P, c_p from the pair gradient's radius entries (12-15).
  Triplets mixed;
  cell.contact().add_mixed(x, p, mixed);
  SparseMatrix M(x.size(), p.size());
  M.setFromTriplets(mixed.begin(), mixed.end());
  const SparseMatrix P = cell.radii_map();
  const Vector lambda_full = S * lambda;
  Vector numerator = -(P.transpose() * (M.transpose() * lambda_full));  // -lambda^T f_p
  const int ma = cell.master(a), mb = cell.master(b);
  numerator.segment<2>(2 * ma) += d.pair_gradient.segment<2>(12);
  numerator.segment<2>(2 * mb) += d.pair_gradient.segment<2>(14);
  g.radii = -numerator / g.denominator;

  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) {
      const Vector xl = cell.state_derivative_lattice(F, k, l);
      const double cl = d.gradient_x.dot(xl) - lambda_full.dot(c.full_hessian * xl);
      g.lattice(k, l) = -cl / g.denominator;
    }
  return g;
}

RigidCellSpec with_parameters(const RigidCellSpec& spec, const Vector& radii, const Eigen::Matrix2d& lattice) {
  RigidCellSpec out = spec;
  // d_hat stays that of the original cell (the default follows the smallest R, and the
  // criterion's distance must not move with the design).
  if (!(out.activation_distance > 0.0)) {
    double min_major = spec.elements.front().shape.major_radius;
    for (const CellElement& e : spec.elements) min_major = std::min(min_major, e.shape.major_radius);
    out.activation_distance = 1e-3 * min_major;
  }
  for (std::size_t i = 0; i < out.elements.size(); ++i) {
    out.elements[i].shape.major_radius = radii[static_cast<Eigen::Index>(2 * i)];
    out.elements[i].shape.minor_radius = radii[static_cast<Eigen::Index>(2 * i + 1)];
  }
  out.lattice = lattice;
  return out;
}

Vector master_radii(const RigidCellSpec& spec) {
  Vector r(2 * spec.elements.size());
  for (std::size_t i = 0; i < spec.elements.size(); ++i) {
    r[static_cast<Eigen::Index>(2 * i)] = spec.elements[i].shape.major_radius;
    r[static_cast<Eigen::Index>(2 * i + 1)] = spec.elements[i].shape.minor_radius;
  }
  return r;
}

}  // namespace tailor::interlocking
