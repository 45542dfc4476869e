#include "forward/rods/discrete_rod.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/rods/rod_kinematics.hpp"

namespace tailor {

Eigen::Vector3d parallel_transport(const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                                   const Eigen::Vector3d& w) {
  const Eigen::Vector3d b = u.cross(v);
  const double c = u.dot(v);
  return c * w + b.cross(w) + (2.0 * b.dot(w) / (u + v).squaredNorm()) * b;
}

namespace {

Eigen::Vector3d most_normal_axis(const Eigen::Vector3d& t) {
  Eigen::Index k = 0;
  t.cwiseAbs().minCoeff(&k);
  return Eigen::Vector3d::Unit(k);
}

Eigen::Vector3d normal_part(const Eigen::Vector3d& t, const Eigen::Vector3d& d) {
  return (d - d.dot(t) * t).normalized();
}

// Signed angle about t from the space-parallel transport of a1 (edge before) to a1 (edge after).
double raw_reference_twist(const Eigen::Vector3d& t0, const Eigen::Vector3d& a0, const Eigen::Vector3d& t1,
                           const Eigen::Vector3d& a1) {
  const Eigen::Vector3d u = parallel_transport(t0, t1, a0);
  return std::atan2(u.cross(a1).dot(t1), u.dot(a1));
}

}  // namespace

DiscreteRod::DiscreteRod(Eigen::MatrixX3d rest_positions, int position_offset, int twist_offset,
                         const Eigen::Vector3d& first_director, RodTopology topology)
    : rest_positions_(std::move(rest_positions)),
      position_offset_(position_offset),
      twist_offset_(twist_offset),
      closed_(topology == RodTopology::closed) {
  const int n = num_vertices();
  if (n < 2) throw std::invalid_argument("DiscreteRod: needs at least 2 vertices, got " + std::to_string(n));
  if (closed_ && n < 3)
    throw std::invalid_argument("DiscreteRod: a closed rod needs at least 3 vertices, got " + std::to_string(n));
  if (position_offset < 0 || twist_offset < 0)
    throw std::invalid_argument("DiscreteRod: negative DOF offset");
  const int ne = num_edges();
  const int pos_end = position_offset + 3 * n, twist_end = twist_offset + ne;
  if (position_offset < twist_end && twist_offset < pos_end)
    throw std::invalid_argument("DiscreteRod: position DOFs [" + std::to_string(position_offset) + ", " +
                                std::to_string(pos_end) + ") overlap twist DOFs [" +
                                std::to_string(twist_offset) + ", " + std::to_string(twist_end) + ")");
  if (!rest_positions_.allFinite()) throw std::invalid_argument("DiscreteRod: non-finite rest position");
  for (int j = 0; j < ne; ++j) {
    const Eigen::Vector3d e = rest_positions_.row(edge_end(j)) - rest_positions_.row(j);
    if (!(e.norm() > 0.0))
      throw std::invalid_argument("DiscreteRod: edge " + std::to_string(j) + " has zero rest length");
    tangents_.push_back(e.normalized());
  }
  const Eigen::Vector3d& t0 = tangents_.front();
  Eigen::Vector3d d = first_director;
  if (!d.allFinite() || (d - d.dot(t0) * t0).norm() <= 1e-12 * std::max(1.0, d.norm()))
    d = most_normal_axis(t0);
  directors_.push_back(normal_part(t0, d));
  for (int j = 0; j < num_interior(); ++j) {
    const int k = next_edge(j);
    if (tangents_[j].dot(tangents_[k]) <= -1.0 + 1e-14)
      throw std::invalid_argument("DiscreteRod: edges " + std::to_string(j) + " and " + std::to_string(k) +
                                  " fold back onto each other at rest");
    if (k != 0)
      directors_.push_back(normal_part(tangents_[k], parallel_transport(tangents_[j], tangents_[k], directors_[j])));
  }
  reference_twist_.assign(static_cast<std::size_t>(std::max(0, num_interior())), 0.0);
  if (closed_) {  // the holonomy of space-parallel transport around the loop
    const int last = ne - 1;
    reference_twist_.back() = raw_reference_twist(tangents_[last], directors_[last], tangents_[0], directors_[0]);
  }
}

int DiscreteRod::dof_end() const {
  return std::max(position_offset_ + 3 * num_vertices(), twist_offset_ + num_edges());
}

Eigen::Vector3d DiscreteRod::position(const Vector& x, int vertex) const {
  return x.segment<3>(position_offset_ + 3 * vertex);
}

Eigen::Vector3d DiscreteRod::edge_vector(const Vector& x, int edge) const {
  return position(x, edge_end(edge)) - position(x, edge);
}

void DiscreteRod::write_rest_state(Vector& x) const {
  if (x.size() < dof_end()) throw std::invalid_argument("DiscreteRod::write_rest_state: state too short");
  for (int v = 0; v < num_vertices(); ++v)
    x.segment<3>(position_offset_ + 3 * v) = rest_positions_.row(v).transpose();
  x.segment(twist_offset_, num_edges()).setZero();
}

Eigen::VectorXd DiscreteRod::rest_lengths() const {
  Eigen::VectorXd lengths(num_edges());
  for (int j = 0; j < num_edges(); ++j)
    lengths[j] = (rest_positions_.row(edge_end(j)) - rest_positions_.row(j)).norm();
  return lengths;
}

Eigen::Vector3d DiscreteRod::reference_director(const Vector& x, int edge) const {
  const Eigen::Vector3d t = edge_vector(x, edge).normalized();
  return parallel_transport(stored_tangent(edge), t, stored_director(edge));
}

Eigen::Matrix<double, 3, 2> DiscreteRod::material_frame(const Vector& x, int edge) const {
  const Eigen::Vector3d t = edge_vector(x, edge).normalized();
  const Eigen::Vector3d a1 = parallel_transport(stored_tangent(edge), t, stored_director(edge));
  const Eigen::Vector3d a2 = t.cross(a1);
  const double theta = x[twist_dof(edge)];
  Eigen::Matrix<double, 3, 2> frame;
  frame.col(0) = std::cos(theta) * a1 + std::sin(theta) * a2;
  frame.col(1) = std::cos(theta) * a2 - std::sin(theta) * a1;
  return frame;
}

double DiscreteRod::reference_twist(const Vector& x, int interior) const {
  const int j = interior, k = next_edge(interior);
  const Eigen::Vector3d t0 = edge_vector(x, j).normalized(), t1 = edge_vector(x, k).normalized();
  const double raw = raw_reference_twist(t0, reference_director(x, j), t1, reference_director(x, k));
  return raw + rod_detail::nearest_branch_shift(raw, stored_reference_twist(interior));
}

void DiscreteRod::update_reference_frames(const Vector& x) {
  if (x.size() < dof_end())
    throw std::invalid_argument("DiscreteRod::update_reference_frames: state too short");
  std::vector<double> twist(reference_twist_.size());
  for (int i = 0; i < num_interior(); ++i) twist[static_cast<std::size_t>(i)] = reference_twist(x, i);
  for (int j = 0; j < num_edges(); ++j) {
    const Eigen::Vector3d t = edge_vector(x, j).normalized();
    if (!t.allFinite() || t.dot(tangents_[j]) <= -1.0 + 1e-12)
      throw std::runtime_error("DiscreteRod::update_reference_frames: edge " + std::to_string(j) +
                               " turned by pi (or collapsed) since the last update; update more often");
    directors_[j] = normal_part(t, parallel_transport(tangents_[j], t, directors_[j]));
    tangents_[j] = t;
  }
  reference_twist_ = std::move(twist);
}

}  // namespace tailor
