// Free common rigid motions (see free_motions.hpp).
#include "forward/rigid/free_motions.hpp"

#include <cmath>
#include <sstream>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid {

std::vector<FreeMotion> free_motions(const Matrix& motions, const std::vector<int>& held, double length) {
  if (!(length > 0.0)) length = 1.0;
  // Rotation columns scaled by the length, so that every column moves points by O(1).
  Matrix V = motions;
  V.rightCols(3) *= length;
  Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Zero();
  for (int dof : held) {
    if (dof < 0 || dof >= V.rows()) continue;
    const Eigen::Matrix<double, 1, 6> row = V.row(dof);
    gram += row.transpose() * row;
  }
  double scale = 0.0;
  for (int k = 0; k < 6; ++k) scale = std::max(scale, V.col(k).squaredNorm());
  Eigen::Matrix<double, 6, 1> gram_values;
  Eigen::Matrix<double, 6, 6> gram_vectors;
  symmetric_eigen(gram, gram_values, gram_vectors);
  std::vector<Eigen::Matrix<double, 6, 1>> null;
  for (int k = 0; k < 6; ++k)
    if (gram_values[k] <= 1e-10 * scale) null.push_back(gram_vectors.col(k));
  std::vector<FreeMotion> out;
  if (null.empty()) return out;
  // Split the null space into pure translations (no rotation part) and the rest.
  const int k = static_cast<int>(null.size());
  Matrix N(6, k);
  for (int j = 0; j < k; ++j) N.col(j) = null[static_cast<std::size_t>(j)];
  const SingularValueDecomposition svd = singular_value_decomposition(N.bottomRows(3), false, true);
  const Eigen::VectorXd& sigma = svd.singular_values;
  const Matrix W = N * svd.V;  // columns: combinations by the size of their rotation part
  std::vector<FreeMotion> translations, rotations;
  for (int j = 0; j < k; ++j) {
    FreeMotion m;
    m.translation = W.col(j).head<3>();
    const bool rotates = j < sigma.size() && sigma[j] > 1e-8;
    if (rotates) m.rotation = W.col(j).tail<3>() * length;
    if (!rotates) m.translation.normalize();
    // The sign that makes the largest component of the direction positive.
    const Eigen::Vector3d& direction = rotates ? m.rotation : m.translation;
    Eigen::Index largest = 0;
    direction.cwiseAbs().maxCoeff(&largest);
    if (direction[largest] < 0.0) {
      m.translation = -m.translation;
      m.rotation = -m.rotation;
    }
    (rotates ? rotations : translations).push_back(m);
  }
  out = translations;
  out.insert(out.end(), rotations.begin(), rotations.end());
  return out;
}

namespace {
std::string vector_text(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(3);
  const double big = v.cwiseAbs().maxCoeff();
  s << "(";
  for (int i = 0; i < 3; ++i) s << (i ? ", " : "") << (std::abs(v[i]) <= 1e-9 * big ? 0.0 : v[i]);
  s << ")";
  return s.str();
}
}  // namespace

std::string describe_free_motions(const std::vector<FreeMotion>& free, const Eigen::Vector3d& centre) {
  std::string text;
  for (const FreeMotion& m : free) {
    if (!text.empty()) text += "; ";
    const double a2 = m.rotation.squaredNorm();
    if (a2 == 0.0) {
      text += "translation along " + vector_text(m.translation);
      continue;
    }
    // The axis: the points that move only along it, p = centre + a x u / |a|^2.
    const Eigen::Vector3d point = centre + m.rotation.cross(m.translation) / a2;
    text += "rotation about " + vector_text(m.rotation.normalized()) + " through " + vector_text(point);
  }
  return text;
}

Matrix rigid_system_motions(const RigidBodySystem& system, const Vector& q, int num_dofs,
                            const std::vector<std::pair<int, Eigen::Vector3d>>& points,
                            const Eigen::Vector3d& centre) {
  Matrix V = Matrix::Zero(num_dofs, 6);
  auto point = [&](int dof, const Eigen::Vector3d& p) {
    for (int k = 0; k < 3; ++k) {
      V.block<3, 1>(dof, k) = Eigen::Vector3d::Unit(k);
      V.block<3, 1>(dof, 3 + k) = Eigen::Vector3d::Unit(k).cross(p - centre);
    }
  };
  for (int b = 0; b < system.num_bodies(); ++b) {
    point(6 * b, q.segment<3>(6 * b));
    // dR R^T = [J dw]: column l of J is vee(dR/dw_l R^T); a world rotation a needs dw = J^-1 a.
    const RotationDerivatives d = rotation_derivatives(q.segment<3>(6 * b + 3));
    Eigen::Matrix3d J;
    for (int l = 0; l < 3; ++l) J.col(l) = skew_vee(d.first[static_cast<std::size_t>(l)] * d.rotation.transpose());
    const Eigen::Matrix3d inverse = J.inverse();
    V.block<3, 3>(6 * b + 3, 3) = inverse.allFinite() ? inverse : Eigen::Matrix3d::Identity();
  }
  for (const auto& [dof, p] : points) point(dof, p);
  return V;
}

}  // namespace tailor::rigid
