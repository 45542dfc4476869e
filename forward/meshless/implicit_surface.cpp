#include "forward/meshless/implicit_surface.hpp"

#include <Eigen/Geometry>
#include <array>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor {

// Uniform bucket grid over the samples (counting sort by cell).
struct ImplicitSurface::Grid {
  Eigen::Vector3d lo;
  double cell = 1.0;
  Eigen::Vector3i size;
  std::vector<int> begin, items;

  Grid(const Eigen::MatrixXd& X, double cell_size) : cell(cell_size) {
    lo = X.colwise().minCoeff().transpose();
    const Eigen::Vector3d hi = X.colwise().maxCoeff().transpose();
    for (int k = 0; k < 3; ++k) {
      // At most 256 cells per axis (memory); the cell grows when the box is larger.
      cell = std::max(cell, (hi[k] - lo[k]) / 256.0);
    }
    for (int k = 0; k < 3; ++k) size[k] = std::max(1, static_cast<int>(std::floor((hi[k] - lo[k]) / cell)) + 1);
    begin.assign(static_cast<std::size_t>(size.prod()) + 1, 0);
    std::vector<int> key(static_cast<std::size_t>(X.rows()));
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      key[static_cast<std::size_t>(i)] = index(coordinates(X.row(i).transpose()));
      ++begin[static_cast<std::size_t>(key[static_cast<std::size_t>(i)]) + 1];
    }
    for (std::size_t c = 1; c < begin.size(); ++c) begin[c] += begin[c - 1];
    items.resize(static_cast<std::size_t>(X.rows()));
    std::vector<int> fill(begin.begin(), begin.end() - 1);
    for (Eigen::Index i = 0; i < X.rows(); ++i) items[static_cast<std::size_t>(fill[static_cast<std::size_t>(key[static_cast<std::size_t>(i)])]++)] = static_cast<int>(i);
  }
  Eigen::Vector3i coordinates(const Eigen::Vector3d& X) const {
    Eigen::Vector3i c;
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(static_cast<int>(std::floor((X[k] - lo[k]) / cell)), 0, size[k] - 1);
    return c;
  }
  int index(const Eigen::Vector3i& c) const { return c[0] + size[0] * (c[1] + size[1] * c[2]); }
  // Calls visit(i) for every sample in the cells within Chebyshev ring distance [r0, r1] of X's cell.
  template <class Visit>
  void rings(const Eigen::Vector3d& X, int r0, int r1, Visit&& visit) const {
    const Eigen::Vector3i c = coordinates(X);
    for (int z = std::max(0, c[2] - r1); z <= std::min(size[2] - 1, c[2] + r1); ++z)
      for (int y = std::max(0, c[1] - r1); y <= std::min(size[1] - 1, c[1] + r1); ++y)
        for (int x = std::max(0, c[0] - r1); x <= std::min(size[0] - 1, c[0] + r1); ++x) {
          const int ring = std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])});
          if (ring < r0) continue;
          const int k = index({x, y, z});
          for (int j = begin[static_cast<std::size_t>(k)]; j < begin[static_cast<std::size_t>(k) + 1]; ++j) visit(items[static_cast<std::size_t>(j)]);
        }
  }
  // Distance to X's cell's boundary is not tracked: the ring search stops one ring after the
  // first hit, and at a ring whose inner distance exceeds the best found.
  template <class Distance>
  void k_nearest(const Eigen::Vector3d& X, int k, Distance&& distance, std::vector<std::pair<double, int>>& best) const {
    best.clear();
    const int max_ring = size.maxCoeff();
    for (int ring = 0; ring <= max_ring; ++ring) {
      rings(X, ring, ring, [&](int i) { best.emplace_back(distance(i), i); });
      // Points outside ring r lie farther than (r - 1) * cell... from X's cell, i.e. >= r * cell - (offset in cell).
      if (static_cast<int>(best.size()) >= k) {
        std::nth_element(best.begin(), best.begin() + (k - 1), best.end());
        if (best[static_cast<std::size_t>(k - 1)].first <= ring * cell) break;
      }
    }
    std::sort(best.begin(), best.end());
    if (static_cast<int>(best.size()) > k) best.resize(static_cast<std::size_t>(k));
  }
};

namespace {

double wendland(double r) { return r >= 1.0 ? 0.0 : std::pow(1.0 - r, 4) * (4.0 * r + 1.0); }

// A unit tangent t1 of the plane with normal n (t2 = n x t1 completes the frame).
Eigen::Vector3d tangent_of(const Eigen::Vector3d& n) {
  return (std::abs(n[0]) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(n).normalized();
}

}  // namespace

ImplicitSurface::~ImplicitSurface() = default;

ImplicitSurface::ImplicitSurface(OrientedPoints points, ImplicitSurfaceOptions options)
    : points_(std::move(points)), options_(options) {
  if (!(options_.support_factor > 0.0)) throw std::invalid_argument("ImplicitSurface: support_factor must be positive");
  validate_oriented_points(points_);
  const Eigen::MatrixXd& P = points_.positions;
  const int n = points_.size();
  if (n < 8) throw PointInputError(points_.source + ": " + std::to_string(n) + " points are too few for a surface");
  const double diagonal = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  if (!(diagonal > 0.0)) throw PointInputError(points_.source + ": all points coincide");
  // Samples on a surface: spacing ~ diagonal / sqrt(n).
  grid_ = std::make_unique<Grid>(P, 2.0 * diagonal / std::sqrt(static_cast<double>(n)));
  std::vector<double> sixth(static_cast<std::size_t>(n));
  std::vector<std::pair<double, int>> best;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d X = P.row(i).transpose();
    grid_->k_nearest(X, 7, [&](int j) { return (P.row(j).transpose() - X).norm(); }, best);
    sixth[static_cast<std::size_t>(i)] = best.back().first;
  }
  std::nth_element(sixth.begin(), sixth.begin() + n / 2, sixth.end());
  report_.samples = n;
  report_.neighbour_distance = sixth[static_cast<std::size_t>(n / 2)];
  if (!(report_.neighbour_distance > 0.0))
    throw PointInputError(points_.source + ": most points repeat their neighbours (zero sample spacing)");
  report_.support_radius = options_.support_factor * report_.neighbour_distance;
  grid_ = std::make_unique<Grid>(P, report_.support_radius);
  if (options_.check_samples) check_samples();
  if (options_.fit == ImplicitFit::quadric) {
    fit_quadrics();
  } else {
    report_.linear_fits = n;
  }
}

void ImplicitSurface::fit_quadrics() {
  // Ohtake et al. 2003, local bivariate quadric, in coordinates scaled by rho so that the normal
  // equations are O(1): H = h / rho = A U^2 + B U V + C V^2 + D U + E V + G, U = u / rho,
  // V = v / rho; height rows [U^2, UV, V^2, U, V, 1] . c = H_j and slope rows
  // [2U, V, 0, 1, 0, 0] . c = -m_u / m_w, [0, U, 2V, 0, 1, 0] . c = -m_v / m_w, each weighted by
  // w_j = W(|p_j - p_i| / rho).
  const Eigen::MatrixXd& P = points_.positions;
  const Eigen::MatrixXd& N = points_.normals;
  const double rho = report_.support_radius;
  const int n = points_.size();
  fits_.assign(static_cast<std::size_t>(n), LocalFit{});
  using Row = Eigen::Matrix<double, 6, 1>;
  for (int i = 0; i < n; ++i) {
    LocalFit& fit = fits_[static_cast<std::size_t>(i)];
    const Eigen::Vector3d p = P.row(i).transpose(), normal = N.row(i).transpose();
    fit.t1 = tangent_of(normal);
    fit.t2 = normal.cross(fit.t1);
    Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    Row rhs = Row::Zero();
    auto add = [&](const Row& row, double target, double weight) {
      normal_matrix.noalias() += weight * row * row.transpose();
      rhs += weight * target * row;
    };
    int used = 0;
    bool sharp = false;
    for (int j : neighbours(p, rho)) {
      const Eigen::Vector3d m = N.row(j).transpose(), d = (P.row(j).transpose() - p) / rho;
      const double cosine = normal.dot(m);
      if (cosine < 0.0) continue;  // an opposite sheet (a thin wall's other side)
      if (cosine < std::sqrt(0.5)) {
        sharp = true;
        break;
      }
      const double weight = wendland(d.norm());
      if (!(weight > 0.0)) continue;
      const double U = d.dot(fit.t1), V = d.dot(fit.t2), H = d.dot(normal);
      const double mu = m.dot(fit.t1), mv = m.dot(fit.t2);
      add((Row() << U * U, U * V, V * V, U, V, 1.0).finished(), H, weight);
      add((Row() << 2.0 * U, V, 0.0, 1.0, 0.0, 0.0).finished(), -mu / cosine, weight);
      add((Row() << 0.0, U, 2.0 * V, 0.0, 1.0, 0.0).finished(), -mv / cosine, weight);
      ++used;
    }
    bool quadric = !sharp && used >= 6;
    Row coefficients = Row::Zero();
    if (quadric) {
      Row values;
      Eigen::Matrix<double, 6, 6> vectors;
      symmetric_eigen<6>(normal_matrix, values, vectors);
      quadric = values[0] > 1e-8 * values[5];
      if (quadric) {
        coefficients = vectors * ((vectors.transpose() * rhs).array() / values.array()).matrix();
        quadric = coefficients.head<3>().cwiseAbs().maxCoeff() <= 1.0;
      }
    }
    if (!quadric) {
      ++report_.linear_fits;
      continue;
    }
    ++report_.quadric_fits;
    fit.a = coefficients[0] / rho;
    fit.b = coefficients[1] / rho;
    fit.c = coefficients[2] / rho;
    fit.d = coefficients[3];
    fit.e = coefficients[4];
    fit.g = coefficients[5] * rho;
  }
}

double ImplicitSurface::local_value(int i, const Eigen::Vector3d& X) const {
  const Eigen::Vector3d d = X - points_.positions.row(i).transpose();
  const double w = d.dot(points_.normals.row(i).transpose());
  if (fits_.empty()) return w;
  const LocalFit& fit = fits_[static_cast<std::size_t>(i)];
  const double u = d.dot(fit.t1), v = d.dot(fit.t2);
  return w - (fit.a * u * u + fit.b * u * v + fit.c * v * v + fit.d * u + fit.e * v + fit.g);
}

std::vector<int> ImplicitSurface::neighbours(const Eigen::Vector3d& X, double radius) const {
  std::vector<int> out;
  const int reach = static_cast<int>(std::ceil(radius / grid_->cell));
  grid_->rings(X, 0, reach, [&](int i) {
    if ((points_.positions.row(i).transpose() - X).squaredNorm() < radius * radius) out.push_back(i);
  });
  return out;
}

double ImplicitSurface::nearest_distance(const Eigen::Vector3d& X, int* nearest) const {
  std::vector<std::pair<double, int>> best;
  grid_->k_nearest(X, 1, [&](int j) { return (points_.positions.row(j).transpose() - X).norm(); }, best);
  if (nearest) *nearest = best.front().second;
  return best.front().first;
}

double ImplicitSurface::value(const Eigen::Vector3d& X) const {
  const double rho = report_.support_radius;
  double sum = 0.0, weight = 0.0;
  grid_->rings(X, 0, 1, [&](int i) {
    const double w = wendland((X - points_.positions.row(i).transpose()).norm() / rho);
    if (w <= 0.0) return;
    sum += w * local_value(i, X);
    weight += w;
  });
  if (weight > 0.0) return sum / weight;
  int nearest = 0;
  nearest_distance(X, &nearest);
  return (X - points_.positions.row(nearest).transpose()).dot(points_.normals.row(nearest).transpose());
}

double ImplicitSurface::classifying_distance(const Eigen::Vector3d& X) const {
  const double near = nearest_distance(X), f = value(X);
  // Within the support radius f itself approximates the signed distance (to O(rho^2 curvature));
  // beyond it, the distance to the samples less the sample spacing bounds the distance to the
  // surface from below.
  if (near < report_.support_radius) return f;
  const double magnitude = std::max(0.0, near - report_.neighbour_distance);
  return f <= 0.0 ? -magnitude : magnitude;
}

void ImplicitSurface::check_samples() {
  const Eigen::MatrixXd& P = points_.positions;
  const Eigen::MatrixXd& N = points_.normals;
  const double rho = report_.support_radius;
  const std::string& file = points_.source;
  report_.min_neighbours = std::numeric_limits<int>::max();
  std::vector<double> angles;
  for (int i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d p = P.row(i).transpose(), n = N.row(i).transpose();
    std::vector<int> near = neighbours(p, rho);
    near.erase(std::remove(near.begin(), near.end(), i), near.end());
    report_.min_neighbours = std::min(report_.min_neighbours, static_cast<int>(near.size()));
    if (near.size() < 3)
      throw PointInputError(file + ": " + points_.describe(i) + " is isolated: " + std::to_string(near.size()) +
                            " other points within the support radius " + std::to_string(rho));
    // A tangent frame at p.
    const Eigen::Vector3d t1 = tangent_of(n);
    const Eigen::Vector3d t2 = n.cross(t1);
    angles.clear();
    bool feature = false;  // a sharp edge or corner nearby: neighbours with normals apart by over 45 degrees
    for (int j : near) {
      const Eigen::Vector3d d = P.row(j).transpose() - p, m = N.row(j).transpose();
      const double length = d.norm();
      if (!(length > 0.0)) continue;
      const bool same_sheet = std::abs(d.dot(n)) < 0.3 * length && std::abs(d.dot(m)) < 0.3 * length;
      if (same_sheet && n.dot(m) < -0.5)
        throw PointInputError(file + ": inconsistent normals: " + points_.describe(i) + " and " + points_.describe(j) +
                              " lie on the same sheet with opposite normals");
      // Every neighbour but those of an opposite sheet (a thin wall's other side) closes the
      // fan around p: at an edge or corner of the solid the other faces' samples project beyond
      // the edge, at a boundary of an open sample set nothing does.
      const Eigen::Vector2d projected(d.dot(t1), d.dot(t2));
      if (n.dot(m) > -0.5 && projected.norm() > 0.1 * length) angles.push_back(std::atan2(projected[1], projected[0]));
      if (n.dot(m) > -0.5 && n.dot(m) < std::sqrt(0.5)) feature = true;
    }
    // A sheet crossing p's: a pair of neighbours off p's tangent plane on both sides of it, on
    // one plane with each other (same orientation, their difference in their tangent plane) that
    // is not p's. At an edge of a closed solid the other face lies on one side only (behind p at
    // a convex edge, in front at a concave one), and so does a thin wall's other side.
    std::vector<int> above, below;
    for (int j : near) {
      const Eigen::Vector3d d = P.row(j).transpose() - p;
      const Eigen::Vector3d m = N.row(j).transpose();
      if (std::abs(n.dot(m)) > 0.9) continue;  // parallel to p's sheet
      if (d.dot(n) > 0.3 * d.norm()) above.push_back(j);
      if (d.dot(n) < -0.3 * d.norm()) below.push_back(j);
    }
    for (int j : above)
      for (int k : below) {
        const Eigen::Vector3d m = N.row(j).transpose(), e = P.row(k).transpose() - P.row(j).transpose();
        if (m.dot(N.row(k).transpose()) > 0.9 && std::abs(e.dot(m)) < 0.3 * e.norm())
          throw PointInputError(file + ": the sample set intersects itself near " + points_.describe(i) + ": " +
                                points_.describe(j) + " and " + points_.describe(k) +
                                " lie on a sheet crossing its tangent plane");
      }
    // At a corner of a closed solid the fan is legitimately incomplete (the solid angle beyond
    // the corner holds no samples): the check is for smooth boundaries only.
    if (feature || angles.size() < 3) continue;
    std::sort(angles.begin(), angles.end());
    double gap = angles.front() + 2.0 * M_PI - angles.back();
    for (std::size_t k = 1; k < angles.size(); ++k) gap = std::max(gap, angles[k] - angles[k - 1]);
    report_.max_boundary_gap = std::max(report_.max_boundary_gap, gap);
    if (gap > 5.0 * M_PI / 6.0)
      throw PointInputError(file + ": the sample set is open: " + points_.describe(i) +
                            " lies on a boundary (its neighbours leave a gap of " + std::to_string(gap * 180.0 / M_PI) +
                            " degrees around it)");
  }
  const Eigen::Vector3d lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.1 * (hi - lo).norm());
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d X((c & 1) ? hi[0] + margin[0] : lo[0] - margin[0], (c & 2) ? hi[1] + margin[1] : lo[1] - margin[1],
                            (c & 4) ? hi[2] + margin[2] : lo[2] - margin[2]);
    if (value(X) <= 0.0) {
      int nearest = 0;
      nearest_distance(X, &nearest);
      throw PointInputError(file + ": the normals point inwards (or the surface is not closed): the space outside is "
                                   "classified as inside near " + points_.describe(nearest));
    }
  }
}

AnalyticShape ImplicitSurface::shape(std::shared_ptr<const ImplicitSurface> surface) {
  AnalyticShape s;
  s.name = surface->points_.source;
  s.signed_distance = [surface](const Eigen::Vector3d& X) { return surface->classifying_distance(X); };
  s.inside_value = [surface](const Eigen::Vector3d& X) { return surface->value(X); };
  s.lo = surface->points_.positions.colwise().minCoeff().transpose();
  s.hi = surface->points_.positions.colwise().maxCoeff().transpose();
  return s;
}

}  // namespace tailor
