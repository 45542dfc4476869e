#include "forward/meshless/covering_patches.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace tailor {

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
