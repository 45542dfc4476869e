#include "forward/meshless/mls_shape_functions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor {

namespace {

std::string format_point(const Eigen::Vector3d& X) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << X[0] << ", " << X[1] << ", " << X[2] << ")";
  return s.str();
}

// The basis at xi (already shifted and scaled), m = 4 or 10.
void basis(const Eigen::Vector3d& xi, int m, double* p) {
  p[0] = 1.0;
  p[1] = xi[0];
  p[2] = xi[1];
  p[3] = xi[2];
  if (m == 10) {
    p[4] = xi[0] * xi[0];
    p[5] = xi[1] * xi[1];
    p[6] = xi[2] * xi[2];
    p[7] = xi[0] * xi[1];
    p[8] = xi[1] * xi[2];
    p[9] = xi[2] * xi[0];
  }
}

}  // namespace

double MlsShapeFunctions::weight(double r, double* derivative_over_r) {
  if (r >= 1.0) {
    if (derivative_over_r) *derivative_over_r = 0.0;
    return 0.0;
  }
  if (r <= 0.5) {
    if (derivative_over_r) *derivative_over_r = -8.0 + 12.0 * r;
    return 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r;
  }
  if (derivative_over_r) *derivative_over_r = -4.0 * (1.0 - r) * (1.0 - r) / r;
  return 4.0 / 3.0 - 4.0 * r + 4.0 * r * r - 4.0 / 3.0 * r * r * r;
}

MlsShapeFunctions::MlsShapeFunctions(Eigen::MatrixXd nodes, Eigen::VectorXd spacing, MlsOptions options)
    : nodes_(std::move(nodes)), options_(options) {
  if (nodes_.cols() != 3 || nodes_.rows() == 0)
    throw std::invalid_argument("MlsShapeFunctions: nodes must be a non-empty n x 3 matrix");
  if (spacing.size() != nodes_.rows())
    throw std::invalid_argument("MlsShapeFunctions: one spacing per node expected (" + std::to_string(nodes_.rows()) +
                                "), got " + std::to_string(spacing.size()));
  if (!(options_.support_factor > 0.0) || !(options_.max_condition > 1.0))
    throw std::invalid_argument("MlsShapeFunctions: support_factor must be > 0 and max_condition > 1");
  if (!nodes_.allFinite()) throw std::invalid_argument("MlsShapeFunctions: a node position is not finite");
  for (Eigen::Index a = 0; a < spacing.size(); ++a)
    if (!(spacing[a] > 0.0) || !std::isfinite(spacing[a]))
      throw std::invalid_argument("MlsShapeFunctions: the spacing of node " + std::to_string(a) + " is not positive");
  radius_ = options_.support_factor * spacing;
  grid_cell_ = radius_.maxCoeff();
  grid_lo_ = nodes_.colwise().minCoeff().transpose();
  const Eigen::Vector3d extent = nodes_.colwise().maxCoeff().transpose() - grid_lo_;
  for (int k = 0; k < 3; ++k) grid_size_[k] = static_cast<int>(std::floor(extent[k] / grid_cell_)) + 1;
  const std::size_t buckets = static_cast<std::size_t>(grid_size_.cast<long>().prod());
  std::vector<int> bucket_of(static_cast<std::size_t>(nodes_.rows()));
  std::vector<int> count(buckets + 1, 0);
  for (Eigen::Index a = 0; a < nodes_.rows(); ++a) {
    Eigen::Vector3i c;
    for (int k = 0; k < 3; ++k)
      c[k] = std::min(grid_size_[k] - 1, static_cast<int>((nodes_(a, k) - grid_lo_[k]) / grid_cell_));
    const int b = c[0] + grid_size_[0] * (c[1] + grid_size_[1] * c[2]);
    bucket_of[static_cast<std::size_t>(a)] = b;
    ++count[static_cast<std::size_t>(b) + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) count[b + 1] += count[b];
  bucket_begin_ = count;
  bucket_nodes_.assign(static_cast<std::size_t>(nodes_.rows()), 0);
  for (Eigen::Index a = 0; a < nodes_.rows(); ++a)
    bucket_nodes_[static_cast<std::size_t>(count[static_cast<std::size_t>(bucket_of[static_cast<std::size_t>(a)])]++)] =
        static_cast<int>(a);
}

std::vector<int> MlsShapeFunctions::covering_nodes(const Eigen::Vector3d& X) const {
  std::vector<int> out;
  // Bucket coordinates, clamped to one bucket outside the grid (no node covers points further out).
  Eigen::Vector3i c;
  for (int k = 0; k < 3; ++k) {
    const double t = std::floor((X[k] - grid_lo_[k]) / grid_cell_);
    if (!(t >= -1.0 && t <= grid_size_[k])) return out;
    c[k] = static_cast<int>(t);
  }
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const Eigen::Vector3i b = c + Eigen::Vector3i(dx, dy, dz);
        if ((b.array() < 0).any() || (b.array() >= grid_size_.array()).any()) continue;
        const std::size_t bucket = static_cast<std::size_t>(b[0] + grid_size_[0] * (b[1] + grid_size_[1] * b[2]));
        for (int t = bucket_begin_[bucket]; t < bucket_begin_[bucket + 1]; ++t) {
          const int a = bucket_nodes_[static_cast<std::size_t>(t)];
          if ((X - nodes_.row(a).transpose()).norm() < radius_[a]) out.push_back(a);
        }
      }
  std::sort(out.begin(), out.end());
  return out;
}

MlsValues MlsShapeFunctions::evaluate(const Eigen::Vector3d& X) const {
  if (!X.allFinite()) throw MeshlessPointError("MLS shape functions: the point " + format_point(X) + " is not finite", X);
  const int m = basis_size();
  MlsValues out;
  out.nodes = covering_nodes(X);
  const int n = static_cast<int>(out.nodes.size());
  if (n < m)
    throw MeshlessPointError("MLS shape functions: the point " + format_point(X) + " is covered by " + std::to_string(n) +
                                 " nodes, fewer than the " + std::to_string(m) +
                                 " terms of the basis (increase support_factor or add nodes)",
                             X);
  double scale = 0.0;
  for (int a : out.nodes) scale = std::max(scale, radius_[a]);
  // Plain loops over the small m x n arrays: Eigen's dense products and its templated
  // eigensolver cost more to compile than they save here (m <= 10); the decomposition is
  // forward/core's compiled-once symmetric_eigen.
  const std::size_t mm = static_cast<std::size_t>(m), nn = static_cast<std::size_t>(n);
  std::vector<double> P(mm * nn);  // p_a in column a (column-major, m rows)
  std::vector<double> w(nn);       // w_a
  std::vector<double> dw(3 * nn);  // dw_a / dX_k at 3a + k
  std::vector<double> A(mm * mm, 0.0);
  for (std::size_t t = 0; t < nn; ++t) {
    const int a = out.nodes[t];
    const Eigen::Vector3d d = X - nodes_.row(a).transpose();
    const double R = radius_[a];
    double dw_over_r = 0.0;
    w[t] = weight(d.norm() / R, &dw_over_r);
    for (int k = 0; k < 3; ++k) dw[3 * t + static_cast<std::size_t>(k)] = dw_over_r / (R * R) * d[k];
    double* p = P.data() + mm * t;
    basis((nodes_.row(a).transpose() - X) / scale, m, p);
    for (std::size_t j = 0; j < mm; ++j)
      for (std::size_t i = 0; i < mm; ++i) A[i + mm * j] += w[t] * p[i] * p[j];
  }
  std::vector<double> lambda(mm), V(mm * mm);
  symmetric_eigen_detail::decompose(A.data(), m, lambda.data(), V.data());
  out.condition = lambda[0] > 0.0 ? lambda[mm - 1] / lambda[0] : std::numeric_limits<double>::infinity();
  if (!(out.condition <= options_.max_condition)) {
    std::ostringstream s;
    s << "MLS shape functions: the moment matrix at " << format_point(X) << " (" << n
      << " covering nodes) has condition number " << out.condition << " above max_condition "
      << options_.max_condition << " (nodes nearly coplanar or collinear there; increase support_factor)";
    throw MeshlessPointError(s.str(), X);
  }
  // x = A^-1 b = V diag(1 / lambda) V^T b, in place.
  std::vector<double> c(mm);
  auto solve = [&](double* b) {
    for (std::size_t j = 0; j < mm; ++j) {
      double sum = 0.0;
      for (std::size_t i = 0; i < mm; ++i) sum += V[i + mm * j] * b[i];
      c[j] = sum / lambda[j];
    }
    for (std::size_t i = 0; i < mm; ++i) {
      double sum = 0.0;
      for (std::size_t j = 0; j < mm; ++j) sum += V[i + mm * j] * c[j];
      b[i] = sum;
    }
  };
  // p_a^T b for every covering node a.
  auto project = [&](const double* b, std::vector<double>& result) {
    result.resize(nn);
    for (std::size_t t = 0; t < nn; ++t) {
      double sum = 0.0;
      for (std::size_t i = 0; i < mm; ++i) sum += P[i + mm * t] * b[i];
      result[t] = sum;
    }
  };
  std::vector<double> gamma(mm, 0.0);
  gamma[0] = 1.0;  // p((X - X) / s)
  solve(gamma.data());
  std::vector<double> pg, pdg;  // p_a^T gamma, p_a^T dgamma_k
  project(gamma.data(), pg);
  out.values.resize(n);
  for (std::size_t t = 0; t < nn; ++t) out.values[static_cast<Eigen::Index>(t)] = w[t] * pg[t];
  out.gradients.resize(n, 3);
  std::vector<double> rhs(mm);
  for (int k = 0; k < 3; ++k) {
    // d p(Y - X0) / dX at Y = X0 for a fixed shift X0 = X: e_{k+1} / s (the quadratic terms vanish).
    std::fill(rhs.begin(), rhs.end(), 0.0);
    rhs[static_cast<std::size_t>(k) + 1] = 1.0 / scale;
    for (std::size_t t = 0; t < nn; ++t) {  // - A_k gamma
      const double f = dw[3 * t + static_cast<std::size_t>(k)] * pg[t];
      for (std::size_t i = 0; i < mm; ++i) rhs[i] -= P[i + mm * t] * f;
    }
    solve(rhs.data());
    project(rhs.data(), pdg);
    for (std::size_t t = 0; t < nn; ++t)
      out.gradients(static_cast<Eigen::Index>(t), k) = w[t] * pdg[t] + dw[3 * t + static_cast<std::size_t>(k)] * pg[t];
  }
  return out;
}

Eigen::Vector3d MlsShapeFunctions::interpolate(const Vector& x, const Eigen::Vector3d& X) const {
  if (x.size() != 3 * nodes_.rows())
    throw std::invalid_argument("MlsShapeFunctions::interpolate: x has size " + std::to_string(x.size()) +
                                ", expected " + std::to_string(3 * nodes_.rows()));
  const MlsValues v = evaluate(X);
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (std::size_t t = 0; t < v.nodes.size(); ++t)
    out += v.values[static_cast<Eigen::Index>(t)] * x.segment<3>(3 * v.nodes[t]);
  return out;
}

}  // namespace tailor
