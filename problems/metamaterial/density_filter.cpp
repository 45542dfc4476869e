#include "problems/metamaterial/density_filter.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tailor {

DensityFilter::DensityFilter(const PeriodicCell& cell, double radius) : radius_(radius) {
  const Mesh& mesh = cell.mesh;
  const int dim = mesh.dim();
  double shortest = 1e300;
  for (int k = 0; k < dim; ++k) shortest = std::min(shortest, cell.lattice.col(k).norm());
  if (!(radius > 0.0) || radius > 0.5 * shortest)
    throw std::invalid_argument(
        "DensityFilter: the radius must lie in (0, half the shortest lattice vector], got " +
        std::to_string(radius));
  const int ne = mesh.num_elements();
  const Eigen::VectorXd volumes = element_volumes(mesh);
  // Centroids in fractional coordinates, wrapped into [0, 1).
  const Eigen::MatrixXd inverse = cell.lattice.inverse();
  Eigen::MatrixXd fractional(ne, dim);
  for (int e = 0; e < ne; ++e) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(dim);
    for (int a = 0; a <= dim; ++a) c += mesh.rest_positions.row(mesh.elements(e, a)).transpose();
    c /= dim + 1;
    Eigen::VectorXd f = inverse * (c - cell.origin);
    for (int k = 0; k < dim; ++k) f[k] -= std::floor(f[k]);
    fractional.row(e) = f.transpose();
  }
  // Bucket the centroids on a grid of about r in fractional coordinates (periodic), so each
  // element only looks at nearby buckets.
  std::vector<int> buckets(dim);
  for (int k = 0; k < dim; ++k)
    buckets[k] = std::max(1, static_cast<int>(std::floor(1.0 / (radius * inverse.row(k).norm()))));
  const auto bucket_index = [&](const std::vector<int>& b) {
    int index = 0;
    for (int k = dim - 1; k >= 0; --k)
      index = index * buckets[k] + ((b[k] % buckets[k]) + buckets[k]) % buckets[k];
    return index;
  };
  int total = 1;
  for (int k = 0; k < dim; ++k) total *= buckets[k];
  std::vector<std::vector<int>> members(total);
  std::vector<std::vector<int>> own(ne, std::vector<int>(dim));
  for (int e = 0; e < ne; ++e) {
    for (int k = 0; k < dim; ++k)
      own[e][k] = std::min(buckets[k] - 1, static_cast<int>(fractional(e, k) * buckets[k]));
    members[bucket_index(own[e])].push_back(e);
  }
  Triplets triplets;
  const int neighbours = dim == 2 ? 9 : 27;
  for (int e = 0; e < ne; ++e) {
    std::vector<int> visited;
    double sum = 0.0;
    const std::size_t first = triplets.size();
    for (int c = 0; c < neighbours; ++c) {
      std::vector<int> b = own[e];
      int code = c;
      for (int k = 0; k < dim; ++k, code /= 3) b[k] += code % 3 - 1;
      const int index = bucket_index(b);
      if (std::find(visited.begin(), visited.end(), index) != visited.end()) continue;
      visited.push_back(index);
      for (const int f : members[index]) {
        Eigen::VectorXd df = (fractional.row(f) - fractional.row(e)).transpose();
        for (int k = 0; k < dim; ++k) df[k] -= std::round(df[k]);  // nearest periodic image
        const double distance = (cell.lattice * df).norm();
        const double w = std::max(0.0, radius - distance) * volumes[f];
        if (w > 0.0) {
          triplets.emplace_back(e, f, w);
          sum += w;
        }
      }
    }
    for (std::size_t t = first; t < triplets.size(); ++t)
      triplets[t] = Triplet(triplets[t].row(), triplets[t].col(), triplets[t].value() / sum);
  }
  weights_.resize(ne, ne);
  weights_.setFromTriplets(triplets.begin(), triplets.end());
}

}  // namespace tailor
