#include "forward/reduction/domain_rotations.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor {

Matrix domain_vertex_weights(const Mesh& mesh, const Eigen::VectorXi& element_domain) {
  if (element_domain.size() != mesh.num_elements())
    throw std::invalid_argument("domain_vertex_weights: one domain per element is needed");
  if (mesh.num_elements() == 0) return Matrix::Zero(mesh.num_vertices(), 0);
  const int domains = element_domain.maxCoeff() + 1;
  if (element_domain.minCoeff() < 0) throw std::invalid_argument("domain_vertex_weights: a negative domain");
  const int dim = mesh.dim(), nodes = static_cast<int>(mesh.elements.cols());
  Matrix w = Matrix::Zero(mesh.num_vertices(), domains);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    // |det| of the edge matrix, proportional to the element's volume (area in 2D).
    Matrix edges(dim, dim);
    for (int k = 0; k < dim; ++k)
      edges.col(k) = (mesh.rest_positions.row(mesh.elements(e, k + 1)) - mesh.rest_positions.row(mesh.elements(e, 0)))
                         .transpose();
    const double volume = std::abs(edges.determinant());
    for (int a = 0; a < nodes; ++a) w(mesh.elements(e, a), element_domain[e]) += volume;
  }
  for (int v = 0; v < w.rows(); ++v) {
    const double sum = w.row(v).sum();
    if (sum > 0.0) w.row(v) /= sum;
  }
  return w;
}

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F) {
  // R = F (F^T F)^{-1/2} from the eigen-decomposition of F^T F = V diag(l) V^T.
  const Eigen::Matrix3d C = F.transpose() * F;
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
  symmetric_eigen<3>(C, values, vectors);
  Eigen::Vector3d inverse_stretch;
  for (int k = 0; k < 3; ++k) inverse_stretch[k] = 1.0 / std::sqrt(std::max(values[k], 1e-300));
  return F * vectors * inverse_stretch.asDiagonal() * vectors.transpose();
}

std::vector<Eigen::Matrix3d> fit_domain_rotations(const Mesh& mesh, const Vector& displacement,
                                                  const Vector& vertex_mass, const Matrix& weights) {
  const int nv = mesh.num_vertices();
  if (mesh.dim() != 3) throw std::invalid_argument("fit_domain_rotations: 3D meshes only");
  if (displacement.size() != 3 * nv || vertex_mass.size() != nv || weights.rows() != nv)
    throw std::invalid_argument("fit_domain_rotations: sizes differ from the mesh's " + std::to_string(nv) +
                                " vertices");
  std::vector<Eigen::Matrix3d> rotations(static_cast<std::size_t>(weights.cols()), Eigen::Matrix3d::Identity());
  for (Eigen::Index d = 0; d < weights.cols(); ++d) {
    double total = 0.0;
    Eigen::Vector3d rest_mean = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
    for (int v = 0; v < nv; ++v) {
      const double mu = vertex_mass[v] * weights(v, d);
      if (mu <= 0.0) continue;
      const Eigen::Vector3d X = mesh.rest_positions.row(v).transpose();
      total += mu;
      rest_mean += mu * X;
      mean += mu * (X + displacement.segment<3>(3 * v));
    }
    if (total <= 0.0) continue;
    rest_mean /= total;
    mean /= total;
    Eigen::Matrix3d apq = Eigen::Matrix3d::Zero(), aqq = Eigen::Matrix3d::Zero();
    for (int v = 0; v < nv; ++v) {
      const double mu = vertex_mass[v] * weights(v, d);
      if (mu <= 0.0) continue;
      const Eigen::Vector3d X = mesh.rest_positions.row(v).transpose();
      const Eigen::Vector3d q = X - rest_mean, p = X + displacement.segment<3>(3 * v) - mean;
      apq += mu * p * q.transpose();
      aqq += mu * q * q.transpose();
    }
    // A degenerate (coplanar) region has no deformation gradient: keep the identity.
    if (std::abs(aqq.determinant()) <= 1e-12 * std::pow(aqq.trace(), 3)) continue;
    const Eigen::Matrix3d F = apq * aqq.inverse();
    if (F.determinant() <= 0.0) continue;
    rotations[static_cast<std::size_t>(d)] = polar_rotation(F);
  }
  return rotations;
}

Matrix rotate_basis(const Matrix& basis, const Matrix& weights, const std::vector<Eigen::Matrix3d>& rotations) {
  const Eigen::Index nv = weights.rows();
  if (basis.rows() != 3 * nv || static_cast<Eigen::Index>(rotations.size()) != weights.cols())
    throw std::invalid_argument("rotate_basis: the basis needs 3 rows per weight row and one rotation per domain");
  Matrix rotated(basis.rows(), basis.cols());
  for (Eigen::Index v = 0; v < nv; ++v) {
    Eigen::Matrix3d blend = Eigen::Matrix3d::Zero();
    for (Eigen::Index d = 0; d < weights.cols(); ++d)
      if (weights(v, d) != 0.0) blend += weights(v, d) * rotations[static_cast<std::size_t>(d)];
    rotated.middleRows(3 * v, 3).noalias() = blend * basis.middleRows(3 * v, 3);
  }
  return rotated;
}

Vector vertex_masses(const SparseMatrix& mass) {
  if (mass.rows() % 3 != 0 || mass.rows() != mass.cols())
    throw std::invalid_argument("vertex_masses: a square mass matrix with 3 rows per vertex is needed");
  const Vector row_sums = mass * Vector::Ones(mass.cols());
  Vector m(mass.rows() / 3);
  for (Eigen::Index v = 0; v < m.size(); ++v) m[v] = row_sums[3 * v];
  return m;
}

}  // namespace tailor
