// Bending and sphere contact of the draped macro-scale sheet (see macro_drape_terms.hpp).
#include "forward/interlocking/macro_drape_terms.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace tailor::interlocking {

QuadraticBendingTerm::QuadraticBendingTerm(const Mesh& flat, double bending_stiffness)
    : stiffness_(bending_stiffness) {
  if (flat.dim() != 2 || flat.elements.cols() != 3)
    throw std::invalid_argument("QuadraticBendingTerm: the rest sheet must be a 2D triangle mesh");
  if (!(bending_stiffness >= 0.0))
    throw std::invalid_argument("QuadraticBendingTerm: needs bending_stiffness >= 0");
  const int n = flat.num_vertices();
  std::vector<std::map<int, double>> weights(static_cast<std::size_t>(n));
  std::vector<double> area(static_cast<std::size_t>(n), 0.0);
  std::map<std::pair<int, int>, int> edge_faces;  // interior edges have two
  for (int k = 0; k < flat.num_elements(); ++k) {
    const Eigen::Vector3i v = flat.elements.row(k).transpose();
    for (int a = 0; a < 3; ++a) {
      const int i = v[(a + 1) % 3], j = v[(a + 2) % 3];  // the edge opposite corner a
      const Eigen::Vector2d e1 = (flat.rest_positions.row(i) - flat.rest_positions.row(v[a])).transpose();
      const Eigen::Vector2d e2 = (flat.rest_positions.row(j) - flat.rest_positions.row(v[a])).transpose();
      const double cot = e1.dot(e2) / std::abs(e1.x() * e2.y() - e1.y() * e2.x());
      weights[static_cast<std::size_t>(i)][j] += 0.5 * cot;
      weights[static_cast<std::size_t>(j)][i] += 0.5 * cot;
      ++edge_faces[{std::min(i, j), std::max(i, j)}];
    }
    const Eigen::Vector2d e1 = (flat.rest_positions.row(v[1]) - flat.rest_positions.row(v[0])).transpose();
    const Eigen::Vector2d e2 = (flat.rest_positions.row(v[2]) - flat.rest_positions.row(v[0])).transpose();
    const double a3 = std::abs(e1.x() * e2.y() - e1.y() * e2.x()) / 6.0;
    for (int a = 0; a < 3; ++a) area[static_cast<std::size_t>(v[a])] += a3;
  }
  std::vector<bool> boundary(static_cast<std::size_t>(n), false);
  for (const auto& [edge, count] : edge_faces)
    if (count == 1)
      boundary[static_cast<std::size_t>(edge.first)] = boundary[static_cast<std::size_t>(edge.second)] = true;
  for (int i = 0; i < n; ++i) {
    if (boundary[static_cast<std::size_t>(i)] || weights[static_cast<std::size_t>(i)].empty()) continue;
    Row row;
    row.area = area[static_cast<std::size_t>(i)];
    double diagonal = 0.0;
    for (const auto& [j, w] : weights[static_cast<std::size_t>(i)]) {
      row.vertices.push_back(j);
      row.weights.push_back(-w);
      diagonal += w;
    }
    row.vertices.push_back(i);
    row.weights.push_back(diagonal);
    rows_.push_back(std::move(row));
  }
}

void QuadraticBendingTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  std::size_t slot = 0;
  for (const Row& row : rows_) {
    const double s = stiffness_ / row.area;
    if (request.value || request.gradient) {
      Eigen::Vector3d lx = Eigen::Vector3d::Zero();
      for (std::size_t a = 0; a < row.vertices.size(); ++a)
        lx += row.weights[a] * x.segment<3>(3 * row.vertices[a]);
      if (request.value) *request.value += 0.5 * s * lx.squaredNorm();
      if (request.gradient)
        for (std::size_t a = 0; a < row.vertices.size(); ++a)
          request.gradient->segment<3>(3 * row.vertices[a]) += s * row.weights[a] * lx;
    }
    if (request.hessian_values)
      for (std::size_t a = 0; a < row.vertices.size(); ++a)
        for (std::size_t b = 0; b < row.vertices.size(); ++b)
          for (int d = 0; d < 3; ++d) request.hessian_values[slot++] = s * row.weights[a] * row.weights[b];
  }
}

void QuadraticBendingTerm::hessian_pattern(HessianPattern& pattern) const {
  for (const Row& row : rows_)
    for (int va : row.vertices)
      for (int vb : row.vertices)
        for (int d = 0; d < 3; ++d) pattern.push_back({3 * va + d, 3 * vb + d});
}

SphereObstacleTerm::SphereObstacleTerm(int num_vertices, const Eigen::Vector3d& center, double radius,
                                       double activation, double stiffness)
    : num_vertices_(num_vertices),
      center_(center),
      radius_(radius),
      activation_(activation),
      stiffness_(stiffness) {
  if (num_vertices < 0 || !(radius > 0.0) || !(activation > 0.0) || !(stiffness > 0.0) || !center.allFinite())
    throw std::invalid_argument(
        "SphereObstacleTerm: needs radius, activation and stiffness > 0 and a finite centre");
}

void SphereObstacleTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  const double dh = activation_;
  for (int v = 0; v < num_vertices_; ++v) {
    double* h = request.hessian_values ? request.hessian_values + 9 * v : nullptr;
    if (h) std::fill(h, h + 9, 0.0);
    const Eigen::Vector3d q = x.segment<3>(3 * v) - center_;
    const double len = q.norm();
    const double d = len - radius_;
    if (!(d > 0.0)) {
      if (request.value) *request.value = std::numeric_limits<double>::infinity();
      continue;
    }
    if (d >= dh) continue;
    const double L = std::log(d / dh);
    const double b = -(d - dh) * (d - dh) * L;
    const double b1 = -2.0 * (d - dh) * L - (d - dh) * (d - dh) / d;
    const double b2 = -2.0 * L - 4.0 * (d - dh) / d + (d - dh) * (d - dh) / (d * d);
    const Eigen::Vector3d n = q / len;
    if (request.value) *request.value += stiffness_ * b;
    if (request.gradient) request.gradient->segment<3>(3 * v) += stiffness_ * b1 * n;
    if (h) {
      // b1 < 0 (repulsion), so the tangential part b1 (I - n n^T) / |q| is negative: the projected
      // Hessian keeps only the normal part b2 n n^T (b2 >= 0 below d_hat).
      const Eigen::Matrix3d nn = n * n.transpose();
      Eigen::Matrix3d H = stiffness_ * b2 * nn;
      if (request.hessian_mode == HessianMode::exact)
        H += stiffness_ * b1 / len * (Eigen::Matrix3d::Identity() - nn);
      Eigen::Map<Eigen::Matrix3d> slots(h);
      slots = H;
    }
  }
}

void SphereObstacleTerm::hessian_pattern(HessianPattern& pattern) const {
  for (int v = 0; v < num_vertices_; ++v)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) pattern.push_back({3 * v + r, 3 * v + c});
}

double SphereObstacleTerm::max_step(const Vector& x, const Vector& dx) const {
  double t_max = 1.0;
  for (int v = 0; v < num_vertices_; ++v) {
    const Eigen::Vector3d q = x.segment<3>(3 * v) - center_;
    const Eigen::Vector3d w = dx.segment<3>(3 * v);
    const double d0 = q.norm() - radius_;
    if (!(d0 > 0.0)) return 0.0;
    // First t with |q + t w| = R + d0 / 5: |w|^2 t^2 + 2 (q.w) t + |q|^2 - s^2 = 0.
    const double s = radius_ + 0.2 * d0;
    const double a = w.squaredNorm(), b = q.dot(w), c = q.squaredNorm() - s * s;
    const double disc = b * b - a * c;
    if (a == 0.0 || b >= 0.0 || disc < 0.0) continue;
    const double t = c / (-b + std::sqrt(disc));  // the smaller root, without cancellation
    t_max = std::min(t_max, t);
  }
  return t_max;
}

Eigen::VectorXd SphereObstacleTerm::gaps(const Vector& x) const {
  Eigen::VectorXd g(num_vertices_);
  for (int v = 0; v < num_vertices_; ++v) g[v] = (x.segment<3>(3 * v) - center_).norm() - radius_;
  return g;
}

}  // namespace tailor::interlocking
