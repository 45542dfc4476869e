#include "forward/core/psd_projection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor {
namespace psd_detail {

bool cholesky_accepts(const double* a, int n) {
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, std::abs(a[i * n + i]));
  if (!(scale > 0.0)) {  // zero (or NaN) diagonal: PSD only if A = 0
    for (int i = 0; i < n * n; ++i)
      if (a[i] != 0.0) return false;
    return true;
  }
  // Cholesky of A + delta I, column by column, on a copy of the lower triangle.
  std::array<double, 32 * 32> small;
  std::vector<double> large;
  double* l = small.data();
  if (n > 32) {
    large.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    l = large.data();
  }
  for (int i = 0; i < n * n; ++i) l[i] = a[i];
  const double shift = kPsdShift * scale;
  for (int j = 0; j < n; ++j) {
    double d = l[j * n + j] + shift;
    for (int k = 0; k < j; ++k) d -= l[k * n + j] * l[k * n + j];
    if (!(d > 0.0)) return false;
    const double root = std::sqrt(d);
    l[j * n + j] = root;
    for (int i = j + 1; i < n; ++i) {
      double s = l[j * n + i];
      for (int k = 0; k < j; ++k) s -= l[k * n + i] * l[k * n + j];
      l[j * n + i] = s / root;
    }
  }
  return true;
}

bool project_psd(double* a, int n) {
  if (cholesky_accepts(a, n)) return false;
  Eigen::Map<Eigen::MatrixXd> A(a, n, n);
  Eigen::VectorXd values(n);
  Eigen::MatrixXd vectors(n, n);
  symmetric_eigen_detail::decompose(a, n, values.data(), vectors.data());
  A.noalias() = vectors * values.cwiseMax(0.0).asDiagonal() * vectors.transpose();
  return true;
}

}  // namespace psd_detail
}  // namespace tailor
