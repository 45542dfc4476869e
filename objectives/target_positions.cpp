#include "objectives/target_positions.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace tailor {

TargetPositions::TargetPositions(int dim, std::vector<int> vertices, Matrix targets, Vector weights)
    : dim_(dim), vertices_(std::move(vertices)), targets_(std::move(targets)), weights_(std::move(weights)) {
  const std::string who = "TargetPositions: ";
  if (dim_ < 1) throw std::invalid_argument(who + "dim must be positive, got " + std::to_string(dim_));
  if (vertices_.empty()) throw std::invalid_argument(who + "no vertices selected");
  const auto count = static_cast<Eigen::Index>(vertices_.size());
  std::unordered_set<int> seen;
  for (int v : vertices_) {
    if (v < 0) throw std::invalid_argument(who + "negative vertex index " + std::to_string(v));
    if (!seen.insert(v).second) throw std::invalid_argument(who + "vertex " + std::to_string(v) + " selected twice");
  }
  if (targets_.rows() != count || targets_.cols() != dim_)
    throw std::invalid_argument(who + "targets must be " + std::to_string(count) + " x " + std::to_string(dim_) +
                                ", got " + std::to_string(targets_.rows()) + " x " + std::to_string(targets_.cols()));
  if (!targets_.allFinite()) throw std::invalid_argument(who + "targets are not finite");
  if (weights_.size() == 0) weights_ = Vector::Ones(count);
  if (weights_.size() != count)
    throw std::invalid_argument(who + "expected " + std::to_string(count) + " weights, got " +
                                std::to_string(weights_.size()));
  for (Eigen::Index i = 0; i < count; ++i)
    if (!std::isfinite(weights_[i]) || weights_[i] < 0)
      throw std::invalid_argument(who + "weight " + std::to_string(i) + " must be finite and >= 0");
}

TargetPositions TargetPositions::displacements(const Mesh& mesh, std::vector<int> vertices, const Matrix& displacements,
                                               Vector weights) {
  const int dim = mesh.dim();
  if (displacements.rows() != static_cast<Eigen::Index>(vertices.size()) || displacements.cols() != dim)
    throw std::invalid_argument("TargetPositions: displacements must be " + std::to_string(vertices.size()) + " x " +
                                std::to_string(dim));
  Matrix targets(displacements.rows(), dim);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const int v = vertices[i];
    if (v < 0 || v >= mesh.num_vertices())
      throw std::invalid_argument("TargetPositions: vertex " + std::to_string(v) + " is not in the mesh (" +
                                  std::to_string(mesh.num_vertices()) + " vertices)");
    const auto row = static_cast<Eigen::Index>(i);
    targets.row(row) = mesh.rest_positions.row(v) + displacements.row(row);
  }
  return TargetPositions(dim, std::move(vertices), std::move(targets), std::move(weights));
}

void TargetPositions::check_state(const Vector& x) const {
  if (x.size() % dim_ != 0)
    throw std::invalid_argument("TargetPositions: state size " + std::to_string(x.size()) + " is not a multiple of dim " +
                                std::to_string(dim_));
  const Eigen::Index num_vertices = x.size() / dim_;
  for (int v : vertices_)
    if (v >= num_vertices)
      throw std::invalid_argument("TargetPositions: vertex " + std::to_string(v) + " is not in a state of " +
                                  std::to_string(num_vertices) + " vertices");
}

double TargetPositions::value(const Vector& x, const Vector& p) const {
  (void)p;
  check_state(x);
  double J = 0.0;
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    J += 0.5 * weights_[row] * (x.segment(dim_ * vertices_[i], dim_) - targets_.row(row).transpose()).squaredNorm();
  }
  return J;
}

// dJ/dx_v = w_v (x_v - t_v).
void TargetPositions::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const {
  (void)p;
  check_state(x);
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    gx.segment(dim_ * vertices_[i], dim_) += weights_[row] * (x.segment(dim_ * vertices_[i], dim_) - targets_.row(row).transpose());
  }
}

// J_xx = diag(w_v I) on the selected vertices; no p-dependence.
void TargetPositions::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp,
                                        Vector& out_x, Vector& out_p) const {
  (void)p, (void)dp, (void)out_p;
  check_state(x);
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    out_x.segment(dim_ * vertices_[i], dim_) += weights_[static_cast<Eigen::Index>(i)] * dx.segment(dim_ * vertices_[i], dim_);
}

void TargetPositions::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                                SparseMatrix* dr_dp) const {
  check_state(x);
  const int m = num_residuals();
  r.resize(m);
  Triplets triplets;
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    const double s = std::sqrt(weights_[row]);
    for (int k = 0; k < dim_; ++k) {
      const int ri = dim_ * static_cast<int>(i) + k;
      const int dof = dim_ * vertices_[i] + k;
      r[ri] = s * (x[dof] - targets_(row, k));
      triplets.emplace_back(ri, dof, s);
    }
  }
  if (dr_dx) {
    dr_dx->resize(m, x.size());
    dr_dx->setFromTriplets(triplets.begin(), triplets.end());
  }
  if (dr_dp) {
    dr_dp->resize(m, p.size());
    dr_dp->setZero();
  }
}

}  // namespace tailor
