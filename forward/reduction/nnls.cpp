#include "forward/reduction/nnls.hpp"

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor {
namespace {

// The least-squares solution of A_P z = b on the passive columns (zero elsewhere).
Vector passive_solve(const Matrix& a, const Vector& b, const std::vector<bool>& passive) {
  std::vector<Eigen::Index> columns;
  for (std::size_t k = 0; k < passive.size(); ++k)
    if (passive[k]) columns.push_back(static_cast<Eigen::Index>(k));
  Matrix sub(a.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c) sub.col(static_cast<Eigen::Index>(c)) = a.col(columns[c]);
  const Vector z_sub = pivoted_qr_solve(sub, b).x.col(0);
  Vector z = Vector::Zero(a.cols());
  for (std::size_t c = 0; c < columns.size(); ++c) z[columns[c]] = z_sub[static_cast<Eigen::Index>(c)];
  return z;
}

}  // namespace

NnlsResult nnls(const Matrix& a, const Vector& b, int max_iterations, const Vector* start) {
  if (b.size() != a.rows())
    throw std::invalid_argument("nnls: b has " + std::to_string(b.size()) + " entries, A " +
                                std::to_string(a.rows()) + " rows");
  const Eigen::Index n = a.cols();
  if (start && (start->size() != n || (start->array() < 0.0).any()))
    throw std::invalid_argument("nnls: the start needs " + std::to_string(n) + " non-negative entries");
  if (max_iterations <= 0) max_iterations = 3 * static_cast<int>(n) + 10;
  NnlsResult result;
  result.x = start ? *start : Vector::Zero(n);
  Vector& x = result.x;
  std::vector<bool> passive(static_cast<std::size_t>(n), false);
  for (Eigen::Index k = 0; k < n; ++k) passive[static_cast<std::size_t>(k)] = x[k] > 0.0;
  // Dual tolerance relative to the problem's scale.
  const double tol = 10.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, a.norm() * b.norm());
  // Inner loop: step towards the unconstrained solution on P, stopping at the boundary, until
  // that solution is feasible; x is then the least-squares solution on P.
  const auto settle = [&]() {
    for (Eigen::Index inner = 0; inner <= n; ++inner) {
      const Vector z = passive_solve(a, b, passive);
      bool feasible = true;
      for (Eigen::Index k = 0; k < n; ++k)
        if (passive[static_cast<std::size_t>(k)] && z[k] <= 0.0) feasible = false;
      if (feasible) {
        x = z;
        return;
      }
      double alpha = 1.0;
      for (Eigen::Index k = 0; k < n; ++k)
        if (passive[static_cast<std::size_t>(k)] && z[k] <= 0.0) alpha = std::min(alpha, x[k] / (x[k] - z[k]));
      x += alpha * (z - x);
      // The indices that reached the boundary (to round-off) leave P.
      const double zero = 1e-14 * x.cwiseAbs().maxCoeff();
      for (Eigen::Index k = 0; k < n; ++k)
        if (passive[static_cast<std::size_t>(k)] && x[k] <= zero) {
          passive[static_cast<std::size_t>(k)] = false;
          x[k] = 0.0;
        }
    }
  };
  if (start && x.size() > 0 && (x.array() > 0.0).any()) settle();
  while (result.iterations < max_iterations) {
    const Vector dual = a.transpose() * (b - a * x);
    Eigen::Index best = -1;
    double best_value = tol;
    for (Eigen::Index k = 0; k < n; ++k)
      if (!passive[static_cast<std::size_t>(k)] && dual[k] > best_value) best_value = dual[k], best = k;
    if (best < 0) {
      result.converged = true;
      break;
    }
    ++result.iterations;
    passive[static_cast<std::size_t>(best)] = true;
    settle();
  }
  result.residual = (a * x - b).norm();
  return result;
}

}  // namespace tailor
