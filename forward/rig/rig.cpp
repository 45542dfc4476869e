#include "forward/rig/rig.hpp"
#include "forward/rigid/rotation.hpp"

#include <cmath>
#include <stdexcept>

namespace tailor {
namespace {

using Mat4 = Eigen::Matrix4d;

Mat4 translation(const Eigen::Vector3d& d) {
  Mat4 t = Mat4::Identity();
  t.block<3, 1>(0, 3) = d;
  return t;
}

// G(s), G'(s) and G''(s) of one degree of freedom (order 0, 1, 2).
Mat4 dof_factor(const BoneDof& dof, double s, int order) {
  Mat4 g = Mat4::Zero();
  if (dof.type == BoneDofType::translation) {
    if (order == 0) return translation(s * dof.axis);
    if (order == 1) g.block<3, 1>(0, 3) = dof.axis;
    return g;  // order 2: zero
  }
  const Eigen::Matrix3d k = rigid::cross_matrix(dof.axis), k2 = k * k;
  const double c = std::cos(s), sn = std::sin(s);
  if (order == 0) {
    g.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity() + sn * k + (1.0 - c) * k2;
    g(3, 3) = 1.0;
  } else if (order == 1) {
    g.block<3, 3>(0, 0) = c * k + sn * k2;
  } else {
    g.block<3, 3>(0, 0) = -sn * k + c * k2;
  }
  return g;
}

}  // namespace

Eigen::Matrix<double, 12, 1> vec12(const Eigen::Matrix4d& transform) {
  Eigen::Matrix<double, 12, 1> v;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) v[r + 3 * c] = transform(r, c);
  return v;
}

Rig::Rig(std::vector<Bone> bones, Matrix rest_positions, Matrix weights, std::vector<PoseCorrection> corrections)
    : bones_(std::move(bones)),
      rest_positions_(std::move(rest_positions)),
      weights_(std::move(weights)),
      corrections_(std::move(corrections)) {
  if (bones_.empty()) throw std::invalid_argument("rig: no bones");
  if (rest_positions_.cols() != 3) throw std::invalid_argument("rig: rest positions must be n x 3");
  if (weights_.rows() != rest_positions_.rows() || weights_.cols() != num_bones())
    throw std::invalid_argument("rig: weights must be vertices x bones (" + std::to_string(rest_positions_.rows()) +
                                " x " + std::to_string(num_bones()) + ")");
  for (int b = 0; b < num_bones(); ++b) {
    const Bone& bone = bones_[static_cast<std::size_t>(b)];
    if (bone.parent < -1 || bone.parent >= b)
      throw std::invalid_argument("rig: bone '" + bone.name + "': its parent must be an earlier bone");
    for (const BoneDof& dof : bone.dofs)
      if (std::abs(dof.axis.norm() - 1.0) > 1e-9)
        throw std::invalid_argument("rig: bone '" + bone.name + "': axes must be unit vectors");
    offsets_.push_back(num_parameters_);
    num_parameters_ += static_cast<int>(bone.dofs.size());
  }
  for (int v = 0; v < weights_.rows(); ++v) {
    if (weights_.row(v).minCoeff() < 0.0 || std::abs(weights_.row(v).sum() - 1.0) > 1e-9)
      throw std::invalid_argument("rig: vertex " + std::to_string(v) +
                                  ": skinning weights must be >= 0 and sum to 1");
  }
  for (std::size_t i = 0; i < corrections_.size(); ++i) {
    const PoseCorrection& c = corrections_[i];
    if (c.pose.size() != num_parameters_ || c.displacement.rows() != rest_positions_.rows() ||
        c.displacement.cols() != 3)
      throw std::invalid_argument("rig: pose correction " + std::to_string(i) +
                                  ": needs a pose of size P and an n x 3 displacement");
    for (std::size_t j = 0; j < i; ++j)
      if ((corrections_[j].pose - c.pose).norm() < 1e-12)
        throw std::invalid_argument("rig: pose corrections " + std::to_string(j) + " and " + std::to_string(i) +
                                    " are at the same pose");
  }
}

BoneTransforms Rig::bone_transforms(const Vector& p, bool second_derivatives) const {
  if (p.size() != num_parameters_) throw std::invalid_argument("rig: pose of the wrong size");
  const int P = num_parameters_, B = num_bones();
  BoneTransforms out;
  out.transform.resize(B);
  out.first.assign(B, std::vector<Mat4>(P, Mat4::Zero()));
  if (second_derivatives) out.second.assign(B, std::vector<Mat4>(P * P, Mat4::Zero()));
  for (int b = 0; b < B; ++b) {
    const Bone& bone = bones_[static_cast<std::size_t>(b)];
    const int k0 = offsets_[static_cast<std::size_t>(b)], m = static_cast<int>(bone.dofs.size());
    // L_b and its derivatives in the bone's own parameters: products with one or two factors
    // replaced by their derivatives.
    auto local = [&](int i, int j) {  // i, j: own dof differentiated (-1: none); i == j: second
      Mat4 l = translation(bone.joint);
      for (int d = 0; d < m; ++d) {
        const int order = (d == i) + (d == j);
        l = l * dof_factor(bone.dofs[static_cast<std::size_t>(d)], p[k0 + d], order);
      }
      return Mat4(l * translation(-bone.joint));
    };
    const Mat4 l = local(-1, -1);
    std::vector<Mat4> dl(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i) dl[static_cast<std::size_t>(i)] = local(i, -1);
    const bool root = bone.parent < 0;
    const Mat4 parent = root ? Mat4::Identity() : out.transform[static_cast<std::size_t>(bone.parent)];
    out.transform[static_cast<std::size_t>(b)] = parent * l;
    auto& first = out.first[static_cast<std::size_t>(b)];
    if (!root)
      for (int k = 0; k < k0; ++k) first[k] = out.first[static_cast<std::size_t>(bone.parent)][k] * l;
    for (int i = 0; i < m; ++i) first[k0 + i] = parent * dl[static_cast<std::size_t>(i)];
    if (!second_derivatives) continue;
    auto& second = out.second[static_cast<std::size_t>(b)];
    if (!root) {
      const auto& pf = out.first[static_cast<std::size_t>(bone.parent)];
      const auto& ps = out.second[static_cast<std::size_t>(bone.parent)];
      for (int k = 0; k < k0; ++k) {
        for (int q = 0; q < k0; ++q) second[k * P + q] = ps[k * P + q] * l;
        for (int i = 0; i < m; ++i) {
          second[k * P + k0 + i] = pf[k] * dl[static_cast<std::size_t>(i)];
          second[(k0 + i) * P + k] = second[k * P + k0 + i];
        }
      }
    }
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) second[(k0 + i) * P + k0 + j] = parent * local(i, j);
  }
  return out;
}

PoseWeights Rig::pose_weights(const Vector& p, bool second_derivatives) const {
  std::vector<Vector> poses;
  for (const PoseCorrection& c : corrections_) poses.push_back(c.pose);
  if (poses.empty()) {
    PoseWeights out;
    out.gradient = Matrix::Zero(0, num_parameters_);
    return out;
  }
  return normalized_pose_weights(poses, p, second_derivatives);
}

PoseWeights normalized_pose_weights(const std::vector<Vector>& poses, const Vector& p, bool second_derivatives) {
  const int m = static_cast<int>(poses.size()), P = static_cast<int>(p.size());
  PoseWeights out;
  out.w = Vector::Zero(m);
  out.gradient = Matrix::Zero(m, P);
  if (second_derivatives) out.hessian.assign(m, Matrix::Zero(P, P));
  if (m == 0) return out;
  if (m == 1) {
    out.w[0] = 1.0;
    return out;
  }
  // s_j = |p - p_j|^2 (ds = 2 (p - p_j), d2s = 2 I); psi_i = prod_{j != i} s_j.
  std::vector<double> s(m);
  std::vector<Vector> ds(m);
  for (int j = 0; j < m; ++j) {
    ds[j] = 2.0 * (p - poses[static_cast<std::size_t>(j)]);
    s[j] = 0.25 * ds[j].squaredNorm();
  }
  auto product_except = [&](int a, int b, int c) {
    double r = 1.0;
    for (int j = 0; j < m; ++j)
      if (j != a && j != b && j != c) r *= s[j];
    return r;
  };
  Vector psi(m);
  Matrix dpsi = Matrix::Zero(m, P);
  std::vector<Matrix> d2psi(m, Matrix::Zero(P, P));
  for (int i = 0; i < m; ++i) {
    psi[i] = product_except(i, -1, -1);
    for (int j = 0; j < m; ++j) {
      if (j == i) continue;
      const double pj = product_except(i, j, -1);
      dpsi.row(i) += pj * ds[j].transpose();
      if (!second_derivatives) continue;
      d2psi[i].diagonal().array() += 2.0 * pj;
      for (int k = 0; k < m; ++k)
        if (k != i && k != j) d2psi[i] += product_except(i, j, k) * ds[j] * ds[k].transpose();
    }
  }
  const double d = psi.sum();
  const Vector dd = dpsi.colwise().sum().transpose();
  out.w = psi / d;
  for (int i = 0; i < m; ++i) out.gradient.row(i) = (dpsi.row(i) - out.w[i] * dd.transpose()) / d;
  if (second_derivatives) {
    Matrix d2d = Matrix::Zero(P, P);
    for (int i = 0; i < m; ++i) d2d += d2psi[i];
    for (int i = 0; i < m; ++i) {
      const Vector gw = out.gradient.row(i).transpose();
      out.hessian[i] = (d2psi[i] - out.w[i] * d2d - gw * dd.transpose() - dd * gw.transpose()) / d;
    }
  }
  return out;
}

Vector Rig::rest_shape(const Vector& p) const {
  const BoneTransforms t = bone_transforms(p, false);
  const PoseWeights pw = pose_weights(p, false);
  const int n = num_vertices();
  Vector x = Vector::Zero(3 * n);
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector4d xh(rest_positions_(v, 0), rest_positions_(v, 1), rest_positions_(v, 2), 1.0);
    for (int b = 0; b < num_bones(); ++b) {
      const double wb = weights_(v, b);
      if (wb != 0.0) x.segment<3>(3 * v) += wb * (t.transform[b] * xh).head<3>();
    }
    for (std::size_t i = 0; i < corrections_.size(); ++i)
      x.segment<3>(3 * v) += pw.w[static_cast<int>(i)] * corrections_[i].displacement.row(v).transpose();
  }
  return x;
}

Vector Rig::rest_shape_of(const Vector& p, const std::vector<int>& vertices) const {
  const BoneTransforms t = bone_transforms(p, false);
  const PoseWeights pw = pose_weights(p, false);
  Vector x = Vector::Zero(3 * static_cast<int>(vertices.size()));
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const int v = vertices[k];
    const Eigen::Vector4d xh(rest_positions_(v, 0), rest_positions_(v, 1), rest_positions_(v, 2), 1.0);
    for (int b = 0; b < num_bones(); ++b)
      if (weights_(v, b) != 0.0) x.segment<3>(3 * static_cast<int>(k)) += weights_(v, b) * (t.transform[b] * xh).head<3>();
    for (std::size_t i = 0; i < corrections_.size(); ++i)
      x.segment<3>(3 * static_cast<int>(k)) += pw.w[static_cast<int>(i)] * corrections_[i].displacement.row(v).transpose();
  }
  return x;
}

Matrix Rig::rest_shape_jacobian(const Vector& p) const {
  const BoneTransforms t = bone_transforms(p, false);
  const PoseWeights pw = pose_weights(p, false);
  const int n = num_vertices(), P = num_parameters_;
  Matrix j = Matrix::Zero(3 * n, P);
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector4d xh(rest_positions_(v, 0), rest_positions_(v, 1), rest_positions_(v, 2), 1.0);
    for (int b = 0; b < num_bones(); ++b) {
      const double wb = weights_(v, b);
      if (wb == 0.0) continue;
      for (int k = 0; k < P; ++k) j.block(3 * v, k, 3, 1) += wb * (t.first[b][k] * xh).head<3>();
    }
    for (std::size_t i = 0; i < corrections_.size(); ++i)
      j.middleRows(3 * v, 3) +=
          corrections_[i].displacement.row(v).transpose() * pw.gradient.row(static_cast<int>(i));
  }
  return j;
}

Vector Rig::rest_shape_second(const Vector& p, const Vector& a, const Vector& bvec) const {
  const BoneTransforms t = bone_transforms(p, true);
  const PoseWeights pw = pose_weights(p, true);
  const int n = num_vertices(), P = num_parameters_;
  std::vector<Mat4> contracted(num_bones(), Mat4::Zero());
  for (int b = 0; b < num_bones(); ++b)
    for (int k = 0; k < P; ++k)
      for (int l = 0; l < P; ++l) contracted[b] += a[k] * bvec[l] * t.second[b][k * P + l];
  Vector x = Vector::Zero(3 * n);
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector4d xh(rest_positions_(v, 0), rest_positions_(v, 1), rest_positions_(v, 2), 1.0);
    for (int b = 0; b < num_bones(); ++b)
      if (weights_(v, b) != 0.0) x.segment<3>(3 * v) += weights_(v, b) * (contracted[b] * xh).head<3>();
  }
  for (std::size_t i = 0; i < corrections_.size(); ++i) {
    const double c = a.dot(pw.hessian[i] * bvec);
    for (int v = 0; v < n; ++v) x.segment<3>(3 * v) += c * corrections_[i].displacement.row(v).transpose();
  }
  return x;
}

Vector Rig::rest_shape_acceleration(const PoseMotion& motion) const {
  return rest_shape_jacobian(motion.p) * motion.acceleration +
         rest_shape_second(motion.p, motion.velocity, motion.velocity);
}

Matrix Rig::skinning_basis(int b) const {
  const int n = num_vertices();
  Matrix basis = Matrix::Zero(3 * n, 12);
  for (int v = 0; v < n; ++v) {
    const double wb = weights_(v, b);
    if (wb == 0.0) continue;
    for (int c = 0; c < 4; ++c) {
      const double xc = c < 3 ? rest_positions_(v, c) : 1.0;
      for (int r = 0; r < 3; ++r) basis(3 * v + r, r + 3 * c) = wb * xc;
    }
  }
  return basis;
}

Matrix Rig::bone_accelerations(const PoseMotion& motion) const {
  const BoneTransforms t = bone_transforms(motion.p, true);
  const int P = num_parameters_;
  Matrix out(12, num_bones());
  for (int b = 0; b < num_bones(); ++b) {
    Mat4 acc = Mat4::Zero();
    for (int k = 0; k < P; ++k) {
      acc += motion.acceleration[k] * t.first[b][k];
      for (int l = 0; l < P; ++l) acc += motion.velocity[k] * motion.velocity[l] * t.second[b][k * P + l];
    }
    out.col(b) = vec12(acc);
  }
  return out;
}

Vector Rig::weight_accelerations(const PoseMotion& motion) const {
  const PoseWeights pw = pose_weights(motion.p, true);
  Vector out(pw.w.size());
  for (int i = 0; i < pw.w.size(); ++i)
    out[i] = pw.gradient.row(i).dot(motion.acceleration) + motion.velocity.dot(pw.hessian[i] * motion.velocity);
  return out;
}

}  // namespace tailor
