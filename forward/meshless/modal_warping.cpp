#include "forward/meshless/modal_warping.hpp"
#include "forward/rigid/rotation.hpp"

#include <cmath>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/fem/linear_simplices.hpp"
#include <stdexcept>
#include <string>

namespace tailor {

namespace {

// exp(M) of a 2 x 2 matrix by scaling and squaring with a Taylor series (to round-off).
Eigen::Matrix2d exponential(const Eigen::Matrix2d& M) {
  int squarings = 0;
  double norm = M.cwiseAbs().rowwise().sum().maxCoeff();
  while (norm > 0.25) {
    norm *= 0.5;
    ++squarings;
  }
  const Eigen::Matrix2d A = M / std::ldexp(1.0, squarings);
  Eigen::Matrix2d result = Eigen::Matrix2d::Identity(), term = Eigen::Matrix2d::Identity();
  for (int k = 1; k <= 18; ++k) {
    term = term * A / k;
    result += term;
  }
  for (int s = 0; s < squarings; ++s) result = result * result;
  return result;
}

// W(w)^-1 in closed form (W is the left Jacobian of SO(3)): I - [w]_x / 2 + c [w]_x^2,
// c = (1 - t sin t / (2 (1 - cos t))) / t^2, by its series 1/12 + t^2/720 below t = 1e-3; t < 2 pi.
Eigen::Matrix3d inverse_warping_matrix(const Eigen::Vector3d& w) {
  const double t = w.norm();
  const Eigen::Matrix3d K = rigid::cross_matrix(w);
  const double c = t < 1e-3 ? 1.0 / 12.0 + t * t / 720.0 : (1.0 - t * std::sin(t) / (2.0 * (1.0 - std::cos(t)))) / (t * t);
  return Eigen::Matrix3d::Identity() - 0.5 * K + c * K * K;
}

}  // namespace

Eigen::Matrix3d warping_matrix(const Eigen::Vector3d& w) {
  const double t = w.norm();
  const Eigen::Matrix3d K = rigid::cross_matrix(w);
  // (1 - cos t) / t^2 and (t - sin t) / t^3 by their series below t = 1e-3 (cancellation).
  const double a = t < 1e-3 ? 0.5 - t * t / 24.0 : (1.0 - std::cos(t)) / (t * t);
  const double b = t < 1e-3 ? 1.0 / 6.0 - t * t / 120.0 : (t - std::sin(t)) / (t * t * t);
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

Eigen::Matrix3d rotation_matrix(const Eigen::Vector3d& w) {
  const double t = w.norm();
  const Eigen::Matrix3d K = rigid::cross_matrix(w);
  const double s = t < 1e-4 ? 1.0 - t * t / 6.0 : std::sin(t) / t;
  const double c = t < 1e-4 ? 0.5 - t * t / 24.0 : (1.0 - std::cos(t)) / (t * t);
  return Eigen::Matrix3d::Identity() + s * K + c * K * K;
}

ModalWarpingOperators modal_warping_operators(const MlsShapeFunctions& mls, const Eigen::MatrixXd& modes,
                                              const Eigen::MatrixXd& points) {
  if (modes.rows() != 3 * mls.num_nodes() || points.cols() != 3)
    throw std::invalid_argument("modal_warping_operators: modes must be 3n x r and points m x 3");
  const Eigen::Index m = points.rows(), r = modes.cols();
  ModalWarpingOperators out;
  out.displacement = Eigen::MatrixXd::Zero(3 * m, r);
  out.rotation = Eigen::MatrixXd::Zero(3 * m, r);
  for (Eigen::Index i = 0; i < m; ++i) {
    const MlsValues v = mls.evaluate(points.row(i).transpose());
    for (std::size_t k = 0; k < v.nodes.size(); ++k) {
      const auto Phi = modes.middleRows(3 * static_cast<Eigen::Index>(v.nodes[k]), 3);
      const Eigen::Vector3d g = v.gradients.row(static_cast<Eigen::Index>(k)).transpose();
      out.displacement.middleRows(3 * i, 3) += v.values[static_cast<Eigen::Index>(k)] * Phi;
      // curl u = sum_b grad phi_b x u_b = [grad phi_b]_x u_b.
      out.rotation.middleRows(3 * i, 3) += 0.5 * rigid::cross_matrix(g) * Phi;
    }
  }
  return out;
}

ModalWarpingOperators fem_modal_warping_operators(const Mesh& mesh, const Eigen::MatrixXd& modes) {
  if (mesh.dim() != 3) throw std::invalid_argument("fem_modal_warping_operators: the mesh must be tetrahedral");
  const int n = mesh.num_vertices();
  if (modes.rows() != 3 * n)
    throw std::invalid_argument("fem_modal_warping_operators: modes must have 3 x " + std::to_string(n) +
                                " rows, got " + std::to_string(modes.rows()));
  const LinearSimplices<3> tets(mesh, {}, "fem_modal_warping_operators");
  ModalWarpingOperators out;
  out.displacement = modes;
  out.rotation = Eigen::MatrixXd::Zero(3 * n, modes.cols());
  Eigen::VectorXd volume = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd curl(3, modes.cols());
  for (int e = 0; e < tets.size(); ++e) {
    // 1/2 curl of the P1 field on tet e: 1/2 sum_a grad N_a x u_a.
    curl.setZero();
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d g = tets.gradients[static_cast<std::size_t>(e)].row(a).transpose();
      curl += 0.5 * rigid::cross_matrix(g) * modes.middleRows(3 * tets.vertices[static_cast<std::size_t>(e)][a], 3);
    }
    const double v = tets.volumes[static_cast<std::size_t>(e)];
    for (int a = 0; a < 4; ++a) {
      const int i = tets.vertices[static_cast<std::size_t>(e)][a];
      out.rotation.middleRows(3 * i, 3) += v * curl;
      volume[i] += v;
    }
  }
  for (int i = 0; i < n; ++i)
    if (volume[i] > 0.0) out.rotation.middleRows(3 * i, 3) /= volume[i];
  return out;
}

double ModalRayleighDamping::ratio(double eigenvalue) const {
  const double omega = std::sqrt(eigenvalue);
  return alpha / (2.0 * omega) + beta * omega / 2.0;
}

WarpedModalSimulator::WarpedModalSimulator(ModalWarpingOperators operators, Eigen::VectorXd eigenvalues,
                                           ModalRayleighDamping damping, double time_step, std::vector<ModalHandle> handles,
                                           double handle_stiffness)
    : operators_(std::move(operators)), lambda_(std::move(eigenvalues)), handles_(std::move(handles)),
      stiffness_(handle_stiffness) {
  const Eigen::Index r = lambda_.size();
  if (operators_.displacement.cols() != r || operators_.rotation.cols() != r)
    throw std::invalid_argument("WarpedModalSimulator: one eigenvalue per mode");
  if (!(time_step > 0.0)) throw std::invalid_argument("WarpedModalSimulator: the time step must be positive");
  if (!(damping.alpha >= 0.0) || !(damping.beta >= 0.0))
    throw std::invalid_argument("WarpedModalSimulator: Rayleigh coefficients must be non-negative");
  if (!handles_.empty() && !(stiffness_ > 0.0))
    throw std::invalid_argument("WarpedModalSimulator: handles need a positive handle stiffness");
  for (const ModalHandle& h : handles_) {
    if (h.displacements.rows() != static_cast<Eigen::Index>(h.points.size()) || h.displacements.cols() != 3 ||
        !(h.rotation_weight > 0.0))
      throw std::invalid_argument("WarpedModalSimulator: a handle needs one target displacement per point and a positive rotation weight");
    for (int i : h.points)
      if (i < 0 || i >= operators_.num_points())
        throw std::invalid_argument("WarpedModalSimulator: handle point " + std::to_string(i) + " out of range");
  }
  q_ = Eigen::VectorXd::Zero(r);
  v_ = Eigen::VectorXd::Zero(r);
  // The stiffness the modes step with: Lambda, or K' = Lambda + k G^T G in the basis V.
  Eigen::VectorXd stiffness = lambda_;
  if (!handles_.empty()) {
    // K' = Lambda + k sum (L_i^T L_i + weight C_i^T C_i), by loops over the 3 x r rows (plain
    // loops: Eigen's dynamic products cost seconds of compile time here).
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(r, r);
    for (Eigen::Index j = 0; j < r; ++j) K(j, j) = lambda_[j];
    const auto add_rows = [&](const Eigen::MatrixXd& rows, Eigen::Index first, double weight) {
      for (Eigen::Index c = first; c < first + 3; ++c)
        for (Eigen::Index a = 0; a < r; ++a)
          for (Eigen::Index b = 0; b < r; ++b) K(a, b) += weight * rows(c, a) * rows(c, b);
    };
    for (const ModalHandle& h : handles_)
      for (int i : h.points) {
        add_rows(operators_.displacement, 3 * static_cast<Eigen::Index>(i), stiffness_);
        if (h.rotation) add_rows(operators_.rotation, 3 * static_cast<Eigen::Index>(i), stiffness_ * h.rotation_weight);
      }
    symmetric_eigen<Eigen::Dynamic>(K, stiffness, basis_);
  }
  const double largest = r > 0 ? stiffness.cwiseAbs().maxCoeff() : 0.0;
  for (Eigen::Index j = 0; j < r; ++j) {
    const double lambda = stiffness[j];
    if (!(lambda > 1e-12 * largest) || !std::isfinite(lambda))
      throw std::invalid_argument("WarpedModalSimulator: mode " + std::to_string(j) + " has stiffness " +
                                  std::to_string(lambda) + " (<= 0" + (handles_.empty() ? "" : ": no handle holds it") + ")");
    Eigen::Matrix2d A;
    A << 0.0, 1.0, -lambda, -(damping.alpha + damping.beta * lambda);
    const Eigen::Matrix2d T = exponential(A * time_step);
    transition_.push_back(T);
    // Constant force f: the particular solution q = f / lambda, so the response to a unit force
    // is (I - T) [1 / lambda, 0].
    forcing_.push_back((Eigen::Matrix2d::Identity() - T) * Eigen::Vector2d(1.0 / lambda, 0.0));
  }
}

void WarpedModalSimulator::move_handle(int h, const Eigen::MatrixXd& displacements,
                                       const std::optional<Eigen::Vector3d>& rotation) {
  if (h < 0 || h >= static_cast<int>(handles_.size())) throw std::invalid_argument("move_handle: no handle " + std::to_string(h));
  ModalHandle& handle = handles_[static_cast<std::size_t>(h)];
  if (displacements.rows() != handle.displacements.rows() || displacements.cols() != 3 ||
      rotation.has_value() != handle.rotation.has_value())
    throw std::invalid_argument("move_handle: the same points and kind of handle expected");
  handle.displacements = displacements;
  handle.rotation = rotation;
}

Eigen::VectorXd WarpedModalSimulator::handle_force() const {
  const Eigen::Index r = q_.size();
  Eigen::VectorXd force = Eigen::VectorXd::Zero(r);
  // force += weight * rows^T target, rows the 3 x r block of `rows` starting at `first`.
  const auto add = [&](const Eigen::MatrixXd& rows, Eigen::Index first, const Eigen::Vector3d& target, double weight) {
    for (Eigen::Index a = 0; a < r; ++a)
      force[a] += weight * (rows(first, a) * target[0] + rows(first + 1, a) * target[1] + rows(first + 2, a) * target[2]);
  };
  for (const ModalHandle& h : handles_)
    for (std::size_t k = 0; k < h.points.size(); ++k) {
      const Eigen::Index i = 3 * static_cast<Eigen::Index>(h.points[k]);
      // The linear displacement whose warp is d_i: W(w)^-1 d_i at the target (or current) rotation.
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      if (h.rotation) {
        w = *h.rotation;
      } else {
        for (Eigen::Index a = 0; a < r; ++a) w += operators_.rotation.block<3, 1>(i, a) * q_[a];
      }
      const Eigen::Vector3d g = inverse_warping_matrix(w) * h.displacements.row(static_cast<Eigen::Index>(k)).transpose();
      add(operators_.displacement, i, g, stiffness_);
      if (h.rotation) add(operators_.rotation, i, *h.rotation, stiffness_ * h.rotation_weight);
    }
  return force;
}

void WarpedModalSimulator::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  if (q.size() != q_.size() || v.size() != v_.size()) throw std::invalid_argument("WarpedModalSimulator::set_state: sizes");
  q_ = q;
  v_ = v;
}

Eigen::VectorXd WarpedModalSimulator::modal_force(int point, const Eigen::Vector3d& force) const {
  const auto L = operators_.displacement.middleRows(3 * static_cast<Eigen::Index>(point), 3);
  const auto C = operators_.rotation.middleRows(3 * static_cast<Eigen::Index>(point), 3);
  const Eigen::Vector3d w = C * q_;
  return L.transpose() * (rotation_matrix(w).transpose() * force);
}

Eigen::VectorXd WarpedModalSimulator::modal_force(const Eigen::VectorXd& forces) const {
  if (forces.size() != operators_.displacement.rows())
    throw std::invalid_argument("WarpedModalSimulator::modal_force: one force per point expected");
  const Eigen::VectorXd w = operators_.rotation * q_;
  Eigen::VectorXd rotated(forces.size());
  for (Eigen::Index i = 0; i < forces.size() / 3; ++i)
    rotated.segment<3>(3 * i) = rotation_matrix(w.segment<3>(3 * i)).transpose() * forces.segment<3>(3 * i);
  return operators_.displacement.transpose() * rotated;
}

void WarpedModalSimulator::step(const Eigen::VectorXd& modal_force) {
  if (modal_force.size() != q_.size()) throw std::invalid_argument("WarpedModalSimulator::step: one force per mode expected");
  // Without handles the modes are the stepping basis; with handles, the modes of K' (V^T q).
  const bool rotate = basis_.size() > 0;
  const Eigen::Index r = q_.size();
  Eigen::VectorXd q = q_, v = v_, f = modal_force;
  if (rotate) {
    const Eigen::VectorXd total = modal_force + handle_force();
    for (Eigen::Index j = 0; j < r; ++j) {  // V^T q, V^T v, V^T f (loops: see the constructor)
      q[j] = basis_.col(j).dot(q_);
      v[j] = basis_.col(j).dot(v_);
      f[j] = basis_.col(j).dot(total);
    }
  }
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    const Eigen::Vector2d s = transition_[static_cast<std::size_t>(j)] * Eigen::Vector2d(q[j], v[j]) +
                              forcing_[static_cast<std::size_t>(j)] * f[j];
    q[j] = s[0];
    v[j] = s[1];
  }
  if (!rotate) {
    q_ = q;
    v_ = v;
    return;
  }
  q_.setZero();
  v_.setZero();
  for (Eigen::Index j = 0; j < r; ++j) {
    q_ += q[j] * basis_.col(j);
    v_ += v[j] * basis_.col(j);
  }
}

void WarpedModalSimulator::displacements(Eigen::VectorXd& u, bool warp) const {
  u.noalias() = operators_.displacement * q_;
  if (!warp) return;
  const Eigen::VectorXd w = operators_.rotation * q_;
  for (Eigen::Index i = 0; i < u.size() / 3; ++i)
    u.segment<3>(3 * i) = warping_matrix(w.segment<3>(3 * i)) * u.segment<3>(3 * i).eval();
}

}  // namespace tailor
