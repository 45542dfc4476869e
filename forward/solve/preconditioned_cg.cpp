#include "forward/solve/preconditioned_cg.hpp"

namespace tailor {

PcgResult preconditioned_cg(const SparseMatrix& upper, const SparseCholesky& preconditioner,
                            const Vector& rhs, double relative_tolerance, int max_iterations,
                            Vector& solution) {
  const auto H = upper.selfadjointView<Eigen::Upper>();
  const double rhs_norm = rhs.norm();
  PcgResult result;
  Vector& v = solution;
  v = preconditioner.solve(rhs);
  Vector r = rhs - H * v;
  result.converged = r.norm() <= relative_tolerance * rhs_norm;
  result.initial_relative_residual = rhs_norm > 0.0 ? r.norm() / rhs_norm : 0.0;
  int it = 0;
  if (result.converged) {
    // The preconditioner alone solved it (a factor of a nearby matrix): no search direction
    // is needed, so its back-solve is skipped.
    result.iterations = 1;
    result.relative_residual = rhs_norm > 0.0 ? r.norm() / rhs_norm : 0.0;
    return result;
  }
  Vector s = preconditioner.solve(r);
  Vector d = s;
  double rs = r.dot(s);
  for (; !result.converged && it < max_iterations; ++it) {
    const Vector Hd = H * d;
    const double curvature = d.dot(Hd);
    if (!(curvature > 0.0)) break;  // indefinite: leave it to a factorization
    const double alpha = rs / curvature;
    v += alpha * d;
    r -= alpha * Hd;
    result.converged = r.norm() <= relative_tolerance * rhs_norm;
    if (result.converged) break;
    s = preconditioner.solve(r);
    const double rs_next = r.dot(s);
    d = s + (rs_next / rs) * d;
    rs = rs_next;
  }
  result.iterations = it + 1;
  result.relative_residual = rhs_norm > 0.0 ? r.norm() / rhs_norm : 0.0;
  return result;
}

}  // namespace tailor
