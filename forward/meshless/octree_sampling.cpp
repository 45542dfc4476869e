#include "forward/meshless/octree_sampling.hpp"

#include <array>
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

OctreeSampling sample_shape(const AnalyticShape& shape, const OctreeSamplingOptions& options) {
  const double h = options.spacing;
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("sample_shape: the node spacing must be positive");
  if (options.boundary_depth < 0 || options.boundary_depth > 8)
    throw std::invalid_argument("sample_shape: boundary_depth must be 0 to 8, not " +
                                std::to_string(options.boundary_depth));
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

  OctreeSampling out;
  std::vector<Eigen::Vector3d> nodes;
  for (int k = 0; k <= cells[2]; ++k)
    for (int j = 0; j <= cells[1]; ++j)
      for (int i = 0; i <= cells[0]; ++i) {
        const Eigen::Vector3d X = shape.lo + h * Eigen::Vector3d(i, j, k);
        if (shape.inside_measure(X) <= 1e-9 * h) nodes.push_back(X);
      }
  if (nodes.empty()) throw std::invalid_argument("sample_shape: no node inside " + shape.name + " (spacing too large)");
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        const Eigen::Vector3d lo = shape.lo + h * Eigen::Vector3d(i, j, k);
        const int c = sampler.classify(lo, h);
        if (c > 0) {
          ++out.cells_inside;
          sampler.add_rule(lo, h, false);
        } else if (c == 0) {
          ++out.cells_cut;
          sampler.cut_cell(lo, h, 0);
        }
      }
  out.nodes.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t a = 0; a < nodes.size(); ++a) out.nodes.row(static_cast<Eigen::Index>(a)) = nodes[a].transpose();
  out.spacing = Eigen::VectorXd::Constant(out.nodes.rows(), h);
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
