#include "forward/meshless/octree_sampling.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor {

void gauss_legendre(int order, std::vector<double>& points, std::vector<double>& weights) {
  if (order < 1 || order > 8)
    throw std::invalid_argument("gauss_legendre: order must be 1 to 8, not " + std::to_string(order));
  points.assign(static_cast<std::size_t>(order), 0.0);
  weights.assign(static_cast<std::size_t>(order), 0.0);
  // Newton's iteration on P_n from Chebyshev guesses; P_n and P_n' by the three-term recurrence.
  for (int i = 0; i < order; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (order + 0.5));
    double dp = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= order; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const double pn = order == 1 ? x : p1, pm = order == 1 ? 1.0 : p0;
      dp = order * (x * pn - pm) / (x * x - 1.0);
      const double dx = pn / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    if (order == 1) {
      x = 0.0;
      dp = 1.0;
    }
    points[static_cast<std::size_t>(i)] = x;
    weights[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
}

namespace {

struct Sampler {
  const AnalyticShape& shape;
  int order;
  int depth;
  std::vector<double> gauss_x, gauss_w;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  int leaves_cut = 0;

  void add_rule(const Eigen::Vector3d& lo, double edge, bool clip) {
    const double half = 0.5 * edge, jacobian = half * half * half;
    for (int i = 0; i < order; ++i)
      for (int j = 0; j < order; ++j)
        for (int k = 0; k < order; ++k) {
          const Eigen::Vector3d X = lo + half * Eigen::Vector3d(1.0 + gauss_x[static_cast<std::size_t>(i)],
                                                                 1.0 + gauss_x[static_cast<std::size_t>(j)],
                                                                 1.0 + gauss_x[static_cast<std::size_t>(k)]);
          if (clip && !shape.inside(X)) continue;
          points.push_back(X);
          weights.push_back(jacobian * gauss_w[static_cast<std::size_t>(i)] * gauss_w[static_cast<std::size_t>(j)] *
                            gauss_w[static_cast<std::size_t>(k)]);
        }
  }

  // 1: inside, -1: outside, 0: cut.
  int classify(const Eigen::Vector3d& lo, double edge) const {
    const double d = shape.signed_distance(lo + Eigen::Vector3d::Constant(0.5 * edge));
    const double r = 0.5 * std::sqrt(3.0) * edge;
    return d <= -r ? 1 : d >= r ? -1 : 0;
  }

  void cut_cell(const Eigen::Vector3d& lo, double edge, int level) {
    const int c = classify(lo, edge);
    if (c < 0) return;
    if (c > 0) return add_rule(lo, edge, false);
    if (level == depth) {
      ++leaves_cut;
      return add_rule(lo, edge, true);
    }
    const double half = 0.5 * edge;
    for (int o = 0; o < 8; ++o)
      cut_cell(lo + half * Eigen::Vector3d(o & 1, (o >> 1) & 1, (o >> 2) & 1), half, level + 1);
  }
};

}  // namespace

namespace {

// The node cells (leaves of the node octree) of one root cell, by the rules of the header.
struct NodeCell {
  Eigen::Vector3d lo;
  double edge;
  int level;
  Eigen::Vector3i corner;  // lower corner in units of h 2^-max_level
};

struct NodeRefiner {
  const AnalyticShape& shape;
  const OctreeSamplingOptions& options;
  const Sampler& sampler;
  std::vector<NodeCell> leaves;
  int refined = 0;

  bool box_wants(const Eigen::Vector3d& lo, double edge, int level) const {
    for (const OctreeRefinementBox& b : options.refine_boxes)
      if (b.level > level && (lo.array() <= b.hi.array()).all() && ((lo.array() + edge) >= b.lo.array()).all()) return true;
    return false;
  }
  // Largest depth -d near the cell (probes over the cell enlarged by `edge`) is below `edge`.
  bool thin(const Eigen::Vector3d& lo, double edge) const {
    if (-shape.signed_distance(lo + Eigen::Vector3d::Constant(0.5 * edge)) >= edge) return false;
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j)
        for (int k = 0; k < 7; ++k)
          if (-shape.signed_distance(lo + 0.5 * edge * Eigen::Vector3d(i - 2, j - 2, k - 2)) >= edge) return false;
    return true;
  }
  void refine(const Eigen::Vector3d& lo, double edge, int level, const Eigen::Vector3i& corner) {
    const bool split = level < options.max_level && sampler.classify(lo, edge) >= 0 &&
                       (box_wants(lo, edge, level) || (options.refine_thin && thin(lo, edge)));
    if (!split) {
      leaves.push_back({lo, edge, level, corner});
      return;
    }
    ++refined;
    const double half = 0.5 * edge;
    const int step = 1 << (options.max_level - level - 1);
    for (int o = 0; o < 8; ++o) {
      const Eigen::Vector3i offset(o & 1, (o >> 1) & 1, (o >> 2) & 1);
      refine(lo + half * offset.cast<double>(), half, level + 1, corner + step * offset);
    }
  }
};

}  // namespace

OctreeSampling sample_shape(const AnalyticShape& shape, const OctreeSamplingOptions& options) {
  const double h = options.spacing;
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("sample_shape: the node spacing must be positive");
  if (options.boundary_depth < 0 || options.boundary_depth > 8)
    throw std::invalid_argument("sample_shape: boundary_depth must be 0 to 8, not " +
                                std::to_string(options.boundary_depth));
  if (options.max_level < 0 || options.max_level > 6)
    throw std::invalid_argument("sample_shape: max_level must be 0 to 6, not " + std::to_string(options.max_level));
  for (const OctreeRefinementBox& b : options.refine_boxes)
    if (b.level < 1 || b.level > options.max_level)
      throw std::invalid_argument("sample_shape: a refinement box's level must be 1 to max_level (" +
                                  std::to_string(options.max_level) + "), not " + std::to_string(b.level));
  if (!shape.signed_distance) throw std::invalid_argument("sample_shape: the shape has no signed distance");
  std::array<int, 3> cells{};
  for (int k = 0; k < 3; ++k) {
    const double extent = shape.hi[k] - shape.lo[k];
    if (!(extent > 0.0)) throw std::invalid_argument("sample_shape: empty bounding box of " + shape.name);
    cells[static_cast<std::size_t>(k)] = std::max(1, static_cast<int>(std::ceil(extent / h - 1e-9)));
    if (cells[static_cast<std::size_t>(k)] > 4096)
      throw std::invalid_argument("sample_shape: more than 4096 cells along an axis (spacing too small)");
  }
  Sampler sampler{shape, options.quadrature_order, options.boundary_depth, {}, {}, {}, {}, 0};
  gauss_legendre(options.quadrature_order, sampler.gauss_x, sampler.gauss_w);

  // The node cells, root cell by root cell (z, then y, then x).
  NodeRefiner refiner{shape, options, sampler, {}, 0};
  const int unit = 1 << options.max_level;  // finest cells per root cell edge
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i)
        refiner.refine(shape.lo + h * Eigen::Vector3d(i, j, k), h, 0, unit * Eigen::Vector3i(i, j, k));

  // Nodes at the node cells' corners in the solid, keyed by their lattice index at the finest
  // level (z-major: at max_level 0 the order of the uniform lattice).
  const std::int64_t nx = static_cast<std::int64_t>(cells[0]) * unit + 1, ny = static_cast<std::int64_t>(cells[1]) * unit + 1;
  std::vector<std::pair<std::int64_t, int>> corners;  // (key, level)
  corners.reserve(refiner.leaves.size() * 8);
  for (const NodeCell& c : refiner.leaves) {
    const int step = 1 << (options.max_level - c.level);
    for (int o = 0; o < 8; ++o) {
      const Eigen::Vector3i at = c.corner + step * Eigen::Vector3i(o & 1, (o >> 1) & 1, (o >> 2) & 1);
      corners.emplace_back((static_cast<std::int64_t>(at[2]) * ny + at[1]) * nx + at[0], c.level);
    }
  }
  std::sort(corners.begin(), corners.end());
  std::vector<Eigen::Vector3d> nodes;
  std::vector<int> levels;
  for (std::size_t c = 0; c < corners.size();) {
    std::size_t end = c;
    int finest = 0;
    for (; end < corners.size() && corners[end].first == corners[c].first; ++end) finest = std::max(finest, corners[end].second);
    const std::int64_t key = corners[c].first;
    const Eigen::Vector3d X =
        shape.lo + (h / unit) * Eigen::Vector3d(static_cast<double>(key % nx), static_cast<double>((key / nx) % ny),
                                                static_cast<double>(key / (nx * ny)));
    if (shape.inside_measure(X) <= 1e-9 * h / (1 << finest)) {
      nodes.push_back(X);
      levels.push_back(finest);
    }
    c = end;
  }
  if (nodes.empty()) throw std::invalid_argument("sample_shape: no node inside " + shape.name + " (spacing too large)");

  OctreeSampling out;
  for (const NodeCell& c : refiner.leaves) {
    const int classification = sampler.classify(c.lo, c.edge);
    if (classification > 0) {
      ++out.cells_inside;
      sampler.add_rule(c.lo, c.edge, false);
    } else if (classification == 0) {
      ++out.cells_cut;
      sampler.cut_cell(c.lo, c.edge, 0);
    }
  }
  out.cells_refined = refiner.refined;
  out.nodes.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  out.spacing.resize(out.nodes.rows());
  out.level.resize(out.nodes.rows());
  for (std::size_t a = 0; a < nodes.size(); ++a) {
    const auto row = static_cast<Eigen::Index>(a);
    out.nodes.row(row) = nodes[a].transpose();
    out.level[row] = levels[a];
    out.spacing[row] = h / (1 << levels[a]);
  }
  out.points.resize(static_cast<Eigen::Index>(sampler.points.size()), 3);
  out.weights.resize(static_cast<Eigen::Index>(sampler.weights.size()));
  for (std::size_t q = 0; q < sampler.points.size(); ++q) {
    out.points.row(static_cast<Eigen::Index>(q)) = sampler.points[q].transpose();
    out.weights[static_cast<Eigen::Index>(q)] = sampler.weights[q];
  }
  out.leaves_cut = sampler.leaves_cut;
  return out;
}

}  // namespace tailor
