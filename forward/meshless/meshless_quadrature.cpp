#include "forward/meshless/meshless_quadrature.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tailor {

Eigen::Matrix3d MeshlessQuadrature::deformation_gradient(const Vector& x, int q) const {
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  for (int t = begin[static_cast<std::size_t>(q)]; t < begin[static_cast<std::size_t>(q) + 1]; ++t)
    F.noalias() += x.segment<3>(3 * nodes[static_cast<std::size_t>(t)]) * gradients[static_cast<std::size_t>(t)].transpose();
  return F;
}

double MeshlessQuadrature::interpolate(const Vector& v, int offset, int q) const {
  double s = 0.0;
  for (int t = begin[static_cast<std::size_t>(q)]; t < begin[static_cast<std::size_t>(q) + 1]; ++t)
    s += values[static_cast<std::size_t>(t)] * v[offset + nodes[static_cast<std::size_t>(t)]];
  return s;
}

MeshlessQuadrature build_meshless_quadrature(const MlsShapeFunctions& mls, const Eigen::MatrixXd& points,
                                             const Eigen::VectorXd& weights) {
  if (points.cols() != 3 || points.rows() != weights.size())
    throw std::invalid_argument("build_meshless_quadrature: points must be q x 3 with one weight per point");
  MeshlessQuadrature out;
  out.num_nodes = mls.num_nodes();
  out.begin.push_back(0);
  for (Eigen::Index q = 0; q < points.rows(); ++q) {
    const Eigen::Vector3d X = points.row(q).transpose();
    const MlsValues v = mls.evaluate(X);
    out.points.push_back(X);
    out.weights.push_back(weights[q]);
    out.max_condition = std::max(out.max_condition, v.condition);
    for (std::size_t t = 0; t < v.nodes.size(); ++t) {
      out.nodes.push_back(v.nodes[t]);
      out.values.push_back(v.values[static_cast<Eigen::Index>(t)]);
      out.gradients.push_back(v.gradients.row(static_cast<Eigen::Index>(t)).transpose());
    }
    out.begin.push_back(static_cast<int>(out.nodes.size()));
  }
  return out;
}

Vector meshless_point_forces(const MlsShapeFunctions& mls, const Eigen::MatrixXd& points, const Eigen::VectorXd& weights,
                             const Eigen::MatrixXd& densities) {
  if (points.cols() != 3 || points.rows() != weights.size() || densities.rows() != points.rows() || densities.cols() != 3)
    throw std::invalid_argument("meshless_point_forces: points and densities must be s x 3 with one weight per point");
  Vector f = Vector::Zero(3 * mls.num_nodes());
  for (Eigen::Index s = 0; s < points.rows(); ++s) {
    const MlsValues v = mls.evaluate(points.row(s).transpose());
    for (std::size_t t = 0; t < v.nodes.size(); ++t)
      f.segment<3>(3 * v.nodes[t]) += weights[s] * v.values[static_cast<Eigen::Index>(t)] * densities.row(s).transpose();
  }
  return f;
}

SparseMatrix meshless_mass_matrix(const MeshlessQuadrature& quadrature, double density) {
  if (!(density > 0.0)) throw std::invalid_argument("meshless_mass_matrix: the density must be positive");
  // The scalar node-node matrix first, summed in chunks: a point carries up to ~27^2 pairs, so
  // the triplets of all points at once would take gigabytes on large quadratures.
  const int n = quadrature.num_nodes;
  SparseMatrix scalar(n, n);
  Triplets chunk;
  const auto flush = [&] {
    SparseMatrix part(n, n);
    part.setFromTriplets(chunk.begin(), chunk.end());
    scalar += part;
    chunk.clear();
  };
  for (int q = 0; q < quadrature.num_points(); ++q) {
    const double w = density * quadrature.weights[static_cast<std::size_t>(q)];
    for (int s = quadrature.begin[static_cast<std::size_t>(q)]; s < quadrature.begin[static_cast<std::size_t>(q) + 1]; ++s)
      for (int t = quadrature.begin[static_cast<std::size_t>(q)]; t < quadrature.begin[static_cast<std::size_t>(q) + 1]; ++t)
        chunk.emplace_back(quadrature.nodes[static_cast<std::size_t>(s)], quadrature.nodes[static_cast<std::size_t>(t)],
                           w * quadrature.values[static_cast<std::size_t>(s)] * quadrature.values[static_cast<std::size_t>(t)]);
    if (chunk.size() > (std::size_t{1} << 22)) flush();
  }
  flush();
  Triplets triplets;
  triplets.reserve(3 * static_cast<std::size_t>(scalar.nonZeros()));
  for (int a = 0; a < scalar.outerSize(); ++a)
    for (SparseMatrix::InnerIterator it(scalar, a); it; ++it)
      for (int k = 0; k < 3; ++k)
        triplets.emplace_back(3 * static_cast<int>(it.row()) + k, 3 * static_cast<int>(it.col()) + k, it.value());
  SparseMatrix M(3 * n, 3 * n);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

}  // namespace tailor
