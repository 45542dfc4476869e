#include "forward/rig/pose_space_dynamics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <chrono>
#include <map>
#include <random>
#include <stdexcept>

#include "forward/fem/mass.hpp"
#include "forward/reduction/subspace_elements.hpp"

namespace tailor {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double body_extent(const Matrix& positions) {
  return (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).maxCoeff();
}

// Random reduced poses whose largest vertex displacement is up to `amplitude`.
std::vector<Vector> training_poses(const Matrix& basis, int count, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> scale(0.2, 1.0);
  std::vector<Vector> poses;
  for (int k = 0; k < count; ++k) {
    Vector d(basis.cols());
    for (int i = 0; i < d.size(); ++i) d[i] = normal(rng);
    const Vector u = basis * d;
    double largest = 0.0;
    for (int v = 0; v < u.size() / 3; ++v) largest = std::max(largest, u.segment<3>(3 * v).norm());
    poses.push_back(d * (scale(rng) * amplitude / std::max(largest, 1e-300)));
  }
  return poses;
}

}  // namespace

PoseSpaceBasis PoseSpaceDynamics::build_bases(const Rig& rig, const RiggedBody& body,
                                              const std::vector<ExamplePose>& examples, const PoseSpaceOptions& options,
                                              const SparseMatrix& mass,
                                              std::vector<ExamplePosePrecomputation>& precomputation) {
  if (examples.empty()) throw std::invalid_argument("pose-space dynamics: no example pose");
  std::vector<Matrix> bases;
  precomputation.assign(examples.size(), {});
  for (std::size_t i = 0; i < examples.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    bases.push_back(example_pose_basis(rig, body, examples[i].pose, mass, examples[i].contact_constraints, options.basis));
    precomputation[i].basis_seconds = seconds_since(start);
    precomputation[i].contact_constraints = static_cast<int>(examples[i].contact_constraints.rows());
  }
  return PoseSpaceBasis(std::move(bases), mass);
}

PoseSpaceDynamics::PoseSpaceDynamics(const Rig& rig, const RiggedBody& body, std::vector<ExamplePose> examples,
                                     const PoseSpaceOptions& options, const MovingRestOptions& dynamics)
    : rig_(rig),
      basis_(build_bases(rig, body, examples, options,
                         mass_matrix(body.mesh, body.density, MassLumping::consistent), precomputation_)),
      dynamics_(dynamics),
      material_(make_material<3>(body.material)) {
  if (options.training_poses < 1) throw std::invalid_argument("pose-space dynamics: training_poses >= 1");
  for (const ExamplePose& e : examples) poses_.push_back(e.pose);
  const SparseMatrix mass = mass_matrix(body.mesh, body.density, MassLumping::consistent);
  const int m = static_cast<int>(poses_.size()), r = basis_.size(), ne = body.mesh.num_elements();
  const Vector params = rigged_body_parameters(body);
  const double amplitude =
      options.training_displacement > 0.0 ? options.training_displacement : 0.05 * body_extent(body.mesh.rest_positions);

  // Cubature rule per example pose, on its own rest shape and aligned basis.
  std::map<int, int> union_index;  // mesh element -> elements_ index
  for (int i = 0; i < m; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const Model model = rigged_elastic_model(body, rig.rest_shape(poses_[static_cast<std::size_t>(i)]));
    const SubspaceElements subspace(model, params, basis_.aligned(i));
    const CubatureTraining training =
        cubature_training(subspace, training_poses(basis_.aligned(i), options.training_poses, amplitude, options.seed + i),
                          Matrix::Ones(ne, 1));
    const CubatureRule rule = fit_cubature(training.a, training.b, options.cubature);
    ExamplePosePrecomputation& pre = precomputation_[static_cast<std::size_t>(i)];
    pre.cubature_seconds = seconds_since(start);
    pre.cubature_elements = static_cast<int>(rule.elements.size());
    pre.training_error = rule.training_error;
    for (std::size_t k = 0; k < rule.elements.size(); ++k) {
      const int e = subspace.mesh_element(rule.elements[k]);
      auto [it, added] = union_index.emplace(e, static_cast<int>(elements_.size()));
      if (added) {
        RuleElement element;
        element.vertices = body.mesh.elements.row(e).transpose();
        element.weights = Vector::Zero(m);
        const LameParameters lame = lame_from_young_poisson(body.youngs_modulus[e], body.poisson_ratio[e]);
        element.lambda = lame.lambda;
        element.mu = lame.mu;
        elements_.push_back(std::move(element));
      }
      elements_[static_cast<std::size_t>(it->second)].weights[i] = rule.weights[static_cast<int>(k)];
    }
  }
  std::map<int, int> local;
  for (RuleElement& element : elements_) {
    for (int a = 0; a < 4; ++a) {
      auto [it, added] = local.emplace(element.vertices[a], static_cast<int>(skinned_vertices_.size()));
      if (added) skinned_vertices_.push_back(element.vertices[a]);
      element.local[a] = it->second;
    }
    for (int i = 0; i < m; ++i) {
      Eigen::Matrix<double, 12, Eigen::Dynamic> rows(12, r);
      for (int a = 0; a < 4; ++a) rows.middleRows<3>(3 * a) = basis_.aligned(i).middleRows<3>(3 * element.vertices[a]);
      element.rows.push_back(std::move(rows));
    }
  }

  // Projections of the inertial and gravity forces.
  Matrix skinning(3 * rig.num_vertices(), 12 * rig.num_bones());
  for (int b = 0; b < rig.num_bones(); ++b) skinning.middleCols(12 * b, 12) = rig.skinning_basis(b);
  Matrix corrections(3 * rig.num_vertices(), static_cast<int>(rig.corrections().size()));
  for (std::size_t k = 0; k < rig.corrections().size(); ++k) {
    const Matrix& d = rig.corrections()[k].displacement;
    for (int v = 0; v < d.rows(); ++v) corrections.block<3, 1>(3 * v, static_cast<int>(k)) = d.row(v).transpose();
  }
  Vector g(3 * rig.num_vertices());
  for (int v = 0; v < rig.num_vertices(); ++v) g.segment<3>(3 * v) = body.gravity;
  for (int i = 0; i < m; ++i) {
    const Matrix mu = mass * basis_.aligned(i);
    bone_projection_.push_back(mu.transpose() * skinning);
    correction_projection_.push_back(mu.transpose() * corrections);
    gravity_projection_.push_back(mu.transpose() * g);
  }
}

Vector PoseSpaceDynamics::weights(const Vector& p) const { return normalized_pose_weights(poses_, p, false).w; }

ReducedRigState PoseSpaceDynamics::initial_state(double time) const {
  ReducedRigState s;
  s.time = time;
  s.q = s.v = Vector::Zero(size());
  return s;
}

Vector PoseSpaceDynamics::displacement(const Vector& p, const Vector& q) const {
  return basis_.blend(weights(p)) * q;
}

bool PoseSpaceDynamics::step(const PoseTrajectory& trajectory, const ReducedRigState& current, ReducedRigState& next,
                             int& iterations, std::string& message) const {
  const double h = dynamics_.time_step, c = 1.0 + dynamics_.rayleigh_mass * h;
  const double t1 = current.time + h;
  const int r = size(), m = static_cast<int>(poses_.size());
  const PoseMotion motion = trajectory(t1);
  const Vector w = weights(motion.p);
  const Matrix orthonormalizer = basis_.orthonormalizer(w);

  // Applied forces in the aligned coordinates z = C q, then q.
  Vector applied_z = Vector::Zero(r);
  const bool inertial = dynamics_.inertial_forces;
  const Matrix bone_acc = inertial ? rig_.bone_accelerations(motion) : Matrix();
  const Vector weight_acc = inertial ? rig_.weight_accelerations(motion) : Vector();
  for (int i = 0; i < m; ++i) {
    if (w[i] == 0.0) continue;
    Vector fi = gravity_projection_[static_cast<std::size_t>(i)];
    if (inertial) {
      fi -= bone_projection_[static_cast<std::size_t>(i)] * Eigen::Map<const Vector>(bone_acc.data(), bone_acc.size());
      if (weight_acc.size() > 0) fi -= correction_projection_[static_cast<std::size_t>(i)] * weight_acc;
    }
    applied_z += w[i] * fi;
  }
  const Vector applied = orthonormalizer.transpose() * applied_z;

  // Rule elements on the current rest shape: volume, dvec(F)/dz, weight.
  const Vector rest = rig_.rest_shape_of(motion.p, skinned_vertices_);
  const int count = static_cast<int>(elements_.size());
  std::vector<Eigen::Matrix<double, 9, Eigen::Dynamic>> jacobians(static_cast<std::size_t>(count));
  std::vector<double> scale(static_cast<std::size_t>(count));
  Eigen::Matrix<double, 12, Eigen::Dynamic> rows(12, r);
  for (int k = 0; k < count; ++k) {
    const RuleElement& e = elements_[static_cast<std::size_t>(k)];
    Eigen::Matrix3d dm;
    for (int a = 1; a < 4; ++a) dm.col(a - 1) = rest.segment<3>(3 * e.local[a]) - rest.segment<3>(3 * e.local[0]);
    const Eigen::Matrix3d dm_inverse = dm.inverse();
    Eigen::Matrix<double, 4, 3> grad;
    grad.bottomRows<3>() = dm_inverse;
    grad.row(0) = -dm_inverse.colwise().sum();
    rows.setZero();
    for (int i = 0; i < m; ++i)
      if (w[i] != 0.0) rows.noalias() += w[i] * e.rows[static_cast<std::size_t>(i)];
    Eigen::Matrix<double, 9, Eigen::Dynamic>& jac = jacobians[static_cast<std::size_t>(k)];
    jac.setZero(9, r);
    for (int j = 0; j < 3; ++j)
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) jac.row(i + 3 * j) += grad(a, j) * rows.row(3 * a + i);
    scale[static_cast<std::size_t>(k)] = w.dot(e.weights) * std::abs(dm.determinant()) / 6.0;
  }

  const Vector predicted = current.q + h * current.v / c;
  Vector q = predicted;
  MaterialEvaluation<3> eval;
  Vector force_z(r);
  Matrix stiffness_z(r, r);
  iterations = 0;
  bool converged = false;
  for (int it = 0; it < dynamics_.max_newton_iterations; ++it) {
    const Vector z = orthonormalizer * q;
    force_z.setZero();
    stiffness_z.setZero();
    for (int k = 0; k < count; ++k) {
      const auto& jac = jacobians[static_cast<std::size_t>(k)];
      const double s = scale[static_cast<std::size_t>(k)];
      if (s == 0.0) continue;
      Eigen::Matrix<double, 9, 1> f = jac * z;
      f[0] += 1.0, f[4] += 1.0, f[8] += 1.0;
      const RuleElement& e = elements_[static_cast<std::size_t>(k)];
      material_->evaluate(Eigen::Map<const Eigen::Matrix3d>(f.data()), {e.lambda, e.mu}, true, true, HessianMode::exact,
                          eval);
      force_z.noalias() += s * (jac.transpose() * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(eval.stress.data()));
      const Eigen::Matrix<double, 9, Eigen::Dynamic> tj = eval.tangent * jac;
      stiffness_z.noalias() += s * (jac.transpose() * tj);
    }
    const Vector inertia = (c / (h * h)) * (q - predicted);
    const Vector internal = orthonormalizer.transpose() * force_z;
    const Vector residual = inertia + internal - applied;
    const double tolerance = dynamics_.newton_tolerance * (inertia.norm() + internal.norm() + applied.norm() + 1e-300);
    if (residual.norm() <= tolerance) {
      converged = true;
      break;
    }
    Matrix jacobian = orthonormalizer.transpose() * stiffness_z * orthonormalizer;
    jacobian.diagonal().array() += c / (h * h);
    const Eigen::LDLT<Matrix> ldlt(jacobian);
    const Vector dq = ldlt.solve(residual);
    q -= dq;
    ++iterations;
    // The linearly implicit scheme takes one step; otherwise a step at round-off ends Newton too.
    if (dynamics_.max_newton_iterations == 1 || dq.norm() <= 1e-13 * (1.0 + q.norm())) {
      converged = true;
      break;
    }
  }
  if (!converged || !q.allFinite()) {
    message = "pose-space dynamics: Newton did not converge at t = " + std::to_string(t1);
    return false;
  }
  next.time = t1;
  next.v = (q - current.q) / h;
  next.q = std::move(q);
  return true;
}

}  // namespace tailor
