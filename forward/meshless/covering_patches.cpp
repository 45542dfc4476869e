#include "forward/meshless/covering_patches.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace tailor {

Eigen::VectorXd neighbour_spacing(const Eigen::MatrixXd& nodes, int k) {
  const int n = static_cast<int>(nodes.rows());
  if (nodes.cols() != 3 || k < 1 || k >= n || !nodes.allFinite())
    throw std::invalid_argument("neighbour_spacing: need finite n x 3 nodes and 1 <= k < n (n = " + std::to_string(n) +
                                ", k = " + std::to_string(k) + ")");
  // Buckets of edge c holding about k + 1 nodes each on average, so that a search over the
  // cells within a growing shell finds the k nearest after a few shells.
  const Eigen::Vector3d lo = nodes.colwise().minCoeff().transpose();
  const Eigen::Vector3d extent = nodes.colwise().maxCoeff().transpose() - lo;
  const double longest = extent.maxCoeff();
  if (!(longest > 0.0)) throw std::invalid_argument("neighbour_spacing: all " + std::to_string(n) + " nodes coincide");
  // The box's volume relative to its longest side cubed, at least 1e-9 (flat or straight sets),
  // computed on ratios so that no scale of the coordinates under- or overflows: then
  // c >= 1e-3 longest ((k + 1) / n)^(1/3), and an axis has at most 1000 (n / (k + 1))^(1/3) + 1 cells.
  const Eigen::Vector3d ratio = extent / longest;
  const double c = longest * std::cbrt(std::max(ratio.prod(), 1e-9) * (k + 1) / n);
  Eigen::Vector3i size;
  for (int d = 0; d < 3; ++d) size[d] = std::max(1, static_cast<int>(std::ceil(extent[d] / c)));
  auto cell_of = [&](const Eigen::Vector3d& X) {
    Eigen::Vector3i i;
    for (int d = 0; d < 3; ++d) i[d] = std::clamp(static_cast<int>(std::floor((X[d] - lo[d]) / c)), 0, size[d] - 1);
    return i;
  };
  const long cells = static_cast<long>(size[0]) * size[1] * size[2];
  std::vector<int> begin(static_cast<std::size_t>(cells) + 1, 0), order(static_cast<std::size_t>(n));
  std::vector<long> cell(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a) {
    const Eigen::Vector3i i = cell_of(nodes.row(a).transpose());
    cell[static_cast<std::size_t>(a)] = (static_cast<long>(i[2]) * size[1] + i[1]) * size[0] + i[0];
    ++begin[static_cast<std::size_t>(cell[static_cast<std::size_t>(a)]) + 1];
  }
  for (long i = 0; i < cells; ++i) begin[static_cast<std::size_t>(i) + 1] += begin[static_cast<std::size_t>(i)];
  std::vector<int> fill(begin.begin(), begin.end() - 1);
  for (int a = 0; a < n; ++a) order[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell[static_cast<std::size_t>(a)])]++)] = a;
  Eigen::VectorXd spacing(n);
  std::vector<double> distances;
  for (int a = 0; a < n; ++a) {
    const Eigen::Vector3d X = nodes.row(a).transpose();
    const Eigen::Vector3i centre = cell_of(X);
    // Shells of cells around a's: after shell r every node within r c of X has been seen, so the
    // k-th smallest distance is final once it is at most r c.
    for (int r = 1;; ++r) {
      distances.clear();
      for (int z = std::max(0, centre[2] - r); z <= std::min(size[2] - 1, centre[2] + r); ++z)
        for (int y = std::max(0, centre[1] - r); y <= std::min(size[1] - 1, centre[1] + r); ++y)
          for (int x = std::max(0, centre[0] - r); x <= std::min(size[0] - 1, centre[0] + r); ++x) {
            const long i = (static_cast<long>(z) * size[1] + y) * size[0] + x;
            for (int j = begin[static_cast<std::size_t>(i)]; j < begin[static_cast<std::size_t>(i) + 1]; ++j) {
              const int b = order[static_cast<std::size_t>(j)];
              if (b != a) distances.push_back((nodes.row(b).transpose() - X).norm());
            }
          }
      const bool whole = r >= size.maxCoeff();
      if (static_cast<int>(distances.size()) >= k) {
        std::nth_element(distances.begin(), distances.begin() + (k - 1), distances.end());
        if (whole || distances[static_cast<std::size_t>(k - 1)] <= r * c) {
          spacing[a] = distances[static_cast<std::size_t>(k - 1)];
          break;
        }
      }
      if (whole) throw std::invalid_argument("neighbour_spacing: fewer than k other nodes");  // unreachable: k < n
    }
  }
  if (!(spacing.minCoeff() > 0.0))
    throw std::invalid_argument("neighbour_spacing: coincident nodes (a k-th neighbour at distance 0)");
  return spacing;
}

Eigen::VectorXd cover_points(const Eigen::MatrixXd& nodes, const Eigen::VectorXd& spacing, const Eigen::MatrixXd& points,
                             const MlsOptions& mls, const CoveringOptions& options, CoveringReport* report) {
  if (!(options.target_condition > 1.0) || !(options.reach > 0.0 && options.reach < 1.0) || options.max_passes < 1)
    throw std::invalid_argument("cover_points: target_condition must exceed 1, reach lie in (0, 1), max_passes >= 1");
  MlsOptions check = mls;
  check.max_condition = std::min(mls.max_condition, options.target_condition);
  const int n = static_cast<int>(nodes.rows());
  Eigen::VectorXd s = spacing;
  CoveringReport r;
  r.points = static_cast<int>(points.rows());
  std::vector<char> repaired(static_cast<std::size_t>(points.rows()), 0);
  std::vector<std::pair<double, int>> by_distance(static_cast<std::size_t>(n));
  std::vector<int> failing;
  for (int pass = 0;; ++pass) {
    const MlsShapeFunctions shape_functions(nodes, s, check);
    const int m = shape_functions.basis_size();
    // The first pass checks every point, later ones those that failed: enlarging supports only
    // adds nodes elsewhere.
    std::vector<int> candidates;
    if (pass == 0) {
      candidates.resize(static_cast<std::size_t>(points.rows()));
      for (std::size_t q = 0; q < candidates.size(); ++q) candidates[q] = static_cast<int>(q);
    } else {
      candidates.swap(failing);
    }
    failing.clear();
    for (int q : candidates) {
      try {
        shape_functions.evaluate(points.row(q).transpose());
      } catch (const MeshlessPointError&) {
        failing.push_back(q);
      }
    }
    r.passes = pass + 1;
    if (failing.empty()) break;
    if (pass == options.max_passes) {
      // Report the first point still failing, with the evaluation's own reason.
      const Eigen::Vector3d X = points.row(failing.front()).transpose();
      try {
        shape_functions.evaluate(X);
      } catch (const MeshlessPointError& e) {
        throw MeshlessPointError(std::string("covering: ") + e.what() + "; still so after enlarging its " +
                                     std::to_string(std::min(n, m + 4 * pass)) + " nearest nodes' supports",
                                 X);
      }
    }
    const int k = std::min(n, m + 4 + m * pass);
    for (int q : failing) {
      repaired[static_cast<std::size_t>(q)] = 1;
      const Eigen::Vector3d X = points.row(q).transpose();
      for (int a = 0; a < n; ++a) by_distance[static_cast<std::size_t>(a)] = {(nodes.row(a).transpose() - X).norm(), a};
      std::nth_element(by_distance.begin(), by_distance.begin() + (k - 1), by_distance.end());
      for (int i = 0; i < k; ++i) {
        const auto [distance, a] = by_distance[static_cast<std::size_t>(i)];
        s[a] = std::max(s[a], distance / (options.reach * mls.support_factor));
      }
    }
  }
  for (int a = 0; a < n; ++a)
    if (s[a] > spacing[a]) {
      ++r.nodes_enlarged;
      r.largest_growth = std::max(r.largest_growth, s[a] / spacing[a]);
    }
  r.points_repaired = static_cast<int>(std::count(repaired.begin(), repaired.end(), 1));
  if (report) *report = r;
  return s;
}

}  // namespace tailor
