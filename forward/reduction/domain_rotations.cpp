#include "forward/reduction/domain_rotations.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor {
namespace {

// The unit quaternion (w, x, y, z) of a rotation matrix; Shepperd's method: the largest of
// 1 + trace and 1 + 2 R_kk - trace under the square root, for accuracy at every angle.
Eigen::Vector4d quaternion_of(const Eigen::Matrix3d& R) {
  const double t = R.trace();
  Eigen::Vector4d q;
  if (t >= R(0, 0) && t >= R(1, 1) && t >= R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + t);
    q << 0.25 * s, (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s;
  } else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + R(0, 0) - R(1, 1) - R(2, 2));
    q << (R(2, 1) - R(1, 2)) / s, 0.25 * s, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s;
  } else if (R(1, 1) >= R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + R(1, 1) - R(0, 0) - R(2, 2));
    q << (R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, 0.25 * s, (R(1, 2) + R(2, 1)) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R(2, 2) - R(0, 0) - R(1, 1));
    q << (R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, 0.25 * s;
  }
  return q;
}

// The rotation matrix of a unit quaternion (w, x, y, z).
Eigen::Matrix3d rotation_of(const Eigen::Vector4d& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3d R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return R;
}

}  // namespace

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

Eigen::Matrix3d blend_rotations(const Eigen::Ref<const Eigen::RowVectorXd>& weights,
                                const std::vector<Eigen::Matrix3d>& rotations, RotationBlend blend) {
  if (blend == RotationBlend::linear) {
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (Eigen::Index d = 0; d < weights.size(); ++d)
      if (weights[d] != 0.0) sum += weights[d] * rotations[static_cast<std::size_t>(d)];
    return sum;
  }
  Eigen::Index heaviest = 0;
  weights.maxCoeff(&heaviest);
  if (weights[heaviest] <= 0.0) return Eigen::Matrix3d::Identity();
  if (blend == RotationBlend::nearest) return rotations[static_cast<std::size_t>(heaviest)];
  // q and -q are the same rotation: align every quaternion with the heaviest domain's before
  // summing, so that the normalized sum interpolates along the shorter arc.
  const Eigen::Vector4d reference = quaternion_of(rotations[static_cast<std::size_t>(heaviest)]);
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  for (Eigen::Index d = 0; d < weights.size(); ++d) {
    if (weights[d] == 0.0) continue;
    const Eigen::Vector4d q = quaternion_of(rotations[static_cast<std::size_t>(d)]);
    sum += (q.dot(reference) < 0.0 ? -weights[d] : weights[d]) * q;
  }
  return rotation_of(sum / sum.norm());
}

Matrix rotate_basis(const Matrix& basis, const Matrix& weights, const std::vector<Eigen::Matrix3d>& rotations,
                    RotationBlend blend) {
  const Eigen::Index nv = weights.rows();
  if (basis.rows() != 3 * nv || static_cast<Eigen::Index>(rotations.size()) != weights.cols())
    throw std::invalid_argument("rotate_basis: the basis needs 3 rows per weight row and one rotation per domain");
  Matrix rotated(basis.rows(), basis.cols());
  for (Eigen::Index v = 0; v < nv; ++v)
    rotated.middleRows(3 * v, 3).noalias() = blend_rotations(weights.row(v), rotations, blend) *
                                             basis.middleRows(3 * v, 3);
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
