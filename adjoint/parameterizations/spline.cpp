// p_i = s(t_i): the natural cubic spline s through control values z at the knots, sampled.
//
// Outside [first knot, last knot] s continues linearly with the end slope. A natural spline
// has s'' = 0 at both end knots, so this extension keeps s twice continuously differentiable.
#include <algorithm>
#include <cmath>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

// Curvature operator K (n x n): the knot second derivatives M = K z of the natural spline
// through the values z. M_0 = M_{n-1} = 0 and, for each interior knot i (h_i = t_{i+1} - t_i),
//   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
//       = 6 (z_{i+1} - z_i) / h_i - 6 (z_i - z_{i-1}) / h_{i-1}.
// The right-hand side is linear in z, R z, so K's interior rows are A^{-1} R: one tridiagonal
// solve with all n columns of R as right-hand sides (the solve for each unit vector z = e_j).
// A is symmetric and strictly diagonally dominant, so elimination without pivoting (Thomas)
// is stable. O(n^2) work, done once.
Matrix curvature_operator(const Vector& t) {
  const Eigen::Index n = t.size(), m = n - 2;  // m interior knots
  Matrix K = Matrix::Zero(n, n);
  if (m <= 0) return K;  // two knots: the spline is the straight line, M = 0
  const Vector h = t.tail(n - 1) - t.head(n - 1);
  Vector sub(m), diag(m), super(m);  // A's rows; row r is knot i = r + 1
  Matrix rhs = Matrix::Zero(m, n);
  for (Eigen::Index r = 0; r < m; ++r) {
    const Eigen::Index i = r + 1;
    sub[r] = h[i - 1];
    diag[r] = 2.0 * (h[i - 1] + h[i]);
    super[r] = h[i];
    rhs(r, i - 1) = 6.0 / h[i - 1];
    rhs(r, i) = -6.0 / h[i - 1] - 6.0 / h[i];
    rhs(r, i + 1) = 6.0 / h[i];
  }
  // Forward elimination (sub[0] and super[m-1] multiply the fixed zero end curvatures).
  for (Eigen::Index r = 1; r < m; ++r) {
    const double factor = sub[r] / diag[r - 1];
    diag[r] -= factor * super[r - 1];
    rhs.row(r) -= factor * rhs.row(r - 1);
  }
  // Back substitution into K's interior rows.
  K.row(m) = rhs.row(m - 1) / diag[m - 1];
  for (Eigen::Index r = m - 2; r >= 0; --r) K.row(r + 1) = (rhs.row(r) - super[r] * K.row(r + 2)) / diag[r];
  return K;
}

// Row W(r, :) gives s(t) = W(r, :) z. On [t_i, t_{i+1}] with a = (t_{i+1} - t)/h, b = 1 - a,
//   s(t) = a z_i + b z_{i+1} + h^2/6 ((a^3 - a) M_i + (b^3 - b) M_{i+1}),
// and the end slopes used for extrapolation are s'(t_0) = (z_1 - z_0)/h_0 - h_0/6 M_1 and
// s'(t_{n-1}) = (z_{n-1} - z_{n-2})/h + h/6 M_{n-2} (using M_0 = M_{n-1} = 0).
Matrix weight_matrix(const Vector& knots, const Vector& samples) {
  const Eigen::Index n = knots.size();
  const Matrix K = curvature_operator(knots);
  auto unit = [n](Eigen::Index j) { return Vector::Unit(n, j).transpose(); };
  const double h_first = knots[1] - knots[0], h_last = knots[n - 1] - knots[n - 2];
  const Eigen::RowVectorXd slope_first = (unit(1) - unit(0)) / h_first - h_first / 6.0 * K.row(1);
  const Eigen::RowVectorXd slope_last = (unit(n - 1) - unit(n - 2)) / h_last + h_last / 6.0 * K.row(n - 2);

  Matrix W(samples.size(), n);
  for (Eigen::Index r = 0; r < samples.size(); ++r) {
    const double t = samples[r];
    if (t < knots[0]) {
      W.row(r) = unit(0) + (t - knots[0]) * slope_first;
    } else if (t > knots[n - 1]) {
      W.row(r) = unit(n - 1) + (t - knots[n - 1]) * slope_last;
    } else {
      // Interval i with t_i <= t <= t_{i+1}; the last knot belongs to the last interval.
      const Eigen::Index i = std::clamp<Eigen::Index>(
          std::upper_bound(knots.data(), knots.data() + n, t) - knots.data() - 1, 0, n - 2);
      const double h = knots[i + 1] - knots[i];
      const double a = (knots[i + 1] - t) / h, b = (t - knots[i]) / h;
      W.row(r) = a * unit(i) + b * unit(i + 1) +
                 h * h / 6.0 * ((a * a * a - a) * K.row(i) + (b * b * b - b) * K.row(i + 1));
    }
  }
  return W;
}

// Linear in z: the map is its weight matrix (num_samples x num_knots, small: one column per
// knot), and the second-order term is the inherited zero.
class SplineMap final : public detail::CheckedMap {
 public:
  SplineMap(const Vector& knots, const Vector& samples) : weights_(weight_matrix(knots, samples)) {}
  std::string name() const override {
    return concat("spline(", weights_.cols(), " knots -> ", weights_.rows(), " samples)");
  }
  int num_design() const override { return static_cast<int>(weights_.cols()); }
  int num_params() const override { return static_cast<int>(weights_.rows()); }

 protected:
  Vector do_apply(const Vector& z) const override { return weights_ * z; }
  Vector do_jacobian_times(const Vector&, const Vector& dz) const override { return weights_ * dz; }
  Vector do_jacobian_transpose_times(const Vector&, const Vector& w) const override {
    return weights_.transpose() * w;
  }

 private:
  Matrix weights_;
};

}  // namespace

ParameterizationPtr spline_map(Vector knots, Vector sample_points) {
  if (knots.size() < 2)
    detail::invalid_parameterization("spline_map", concat("needs at least 2 knots, got ", knots.size()));
  for (Eigen::Index i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i]))
      detail::invalid_parameterization("spline_map",
                                       concat("knots must be finite, got knots[", i, "] = ", knots[i]));
    if (i > 0 && !(knots[i] > knots[i - 1]))
      detail::invalid_parameterization(
          "spline_map", concat("knots must be strictly increasing, but knots[", i, "] = ", knots[i],
                               " <= knots[", i - 1, "] = ", knots[i - 1]));
  }
  for (Eigen::Index i = 0; i < sample_points.size(); ++i)
    if (!std::isfinite(sample_points[i]))
      detail::invalid_parameterization(
          "spline_map",
          concat("sample points must be finite, got sample_points[", i, "] = ", sample_points[i]));
  return std::make_shared<SplineMap>(knots, sample_points);
}

}  // namespace tailor
