#include "forward/rig/rigged_body.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "forward/core/elimination.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/mass.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {
namespace {

void check_body(const RiggedBody& body, const Rig& rig) {
  const int ne = body.mesh.num_elements();
  if (body.mesh.dim() != 3) throw std::invalid_argument("rigged body: needs a tet mesh");
  if (body.mesh.num_vertices() != rig.num_vertices())
    throw std::invalid_argument("rigged body: the mesh and the rig have different vertex counts");
  if (body.youngs_modulus.size() != ne || body.poisson_ratio.size() != ne || body.density.size() != ne)
    throw std::invalid_argument("rigged body: Young's modulus, Poisson's ratio and density are per element");
  for (int v : body.fixed_vertices)
    if (v < 0 || v >= body.mesh.num_vertices()) throw std::invalid_argument("rigged body: fixed vertex out of range");
}

}  // namespace

Mesh posed_mesh(const Mesh& mesh, const Vector& rest_shape) {
  Mesh posed = mesh;
  for (int v = 0; v < mesh.num_vertices(); ++v) posed.rest_positions.row(v) = rest_shape.segment<3>(3 * v).transpose();
  return posed;
}

Vector rigged_body_parameters(const RiggedBody& body) {
  Vector p(2 * body.mesh.num_elements());
  p << body.youngs_modulus, body.poisson_ratio;
  return p;
}

std::vector<int> rigged_free_dofs(const RiggedBody& body) {
  std::vector<char> fixed(static_cast<std::size_t>(body.mesh.num_vertices()), 0);
  for (int v : body.fixed_vertices) fixed[static_cast<std::size_t>(v)] = 1;
  std::vector<int> free;
  for (int v = 0; v < body.mesh.num_vertices(); ++v)
    if (!fixed[static_cast<std::size_t>(v)])
      for (int c = 0; c < 3; ++c) free.push_back(3 * v + c);
  return free;
}

Model rigged_elastic_model(const RiggedBody& body, const Vector& rest_shape) {
  const int ne = body.mesh.num_elements();
  Model model(3 * body.mesh.num_vertices());
  model.parameter_layout().add("youngs_modulus", ne);
  model.parameter_layout().add("poisson_ratio", ne);
  std::shared_ptr<const Material<3>> material = make_material<3>(body.material);
  model.add(std::make_unique<ElasticTerm<3>>(posed_mesh(body.mesh, rest_shape), material, 0, ne));
  std::vector<int> fixed_dofs;
  for (int v : body.fixed_vertices)
    for (int c = 0; c < 3; ++c) fixed_dofs.push_back(3 * v + c);
  model.set_elimination(Elimination::dirichlet(fixed_dofs, rest_shape));
  return model;
}

MovingRestDynamics::MovingRestDynamics(const Rig& rig, RiggedBody body, MovingRestOptions options)
    : rig_(rig), body_(std::move(body)), options_(options) {
  check_body(body_, rig_);
  if (!(options_.time_step > 0.0) || !(options_.rayleigh_mass >= 0.0) || options_.max_newton_iterations < 1)
    throw std::invalid_argument("moving rest dynamics: time step > 0, damping >= 0, Newton iterations >= 1");
  mass_ = mass_matrix(body_.mesh, body_.density, MassLumping::consistent);
  params_ = rigged_body_parameters(body_);
  Vector g(3 * body_.mesh.num_vertices());
  for (int v = 0; v < body_.mesh.num_vertices(); ++v) g.segment<3>(3 * v) = body_.gravity;
  gravity_force_ = mass_ * g;
  free_dofs_ = rigged_free_dofs(body_);
}

MovingRestDynamics::~MovingRestDynamics() = default;

MovingRestState MovingRestDynamics::initial_state(double time) const {
  MovingRestState s;
  s.time = time;
  s.u = s.v = Vector::Zero(3 * body_.mesh.num_vertices());
  return s;
}

Vector MovingRestDynamics::applied_force(const PoseMotion& motion) const {
  Vector f = gravity_force_;
  if (options_.inertial_forces) f -= mass_ * rig_.rest_shape_acceleration(motion);
  return f;
}

bool MovingRestDynamics::step(const PoseTrajectory& trajectory, const MovingRestState& current,
                              MovingRestState& next, int& iterations, std::string& message) const {
  const double h = options_.time_step, c = 1.0 + options_.rayleigh_mass * h;
  const double t1 = current.time + h;
  const PoseMotion motion = trajectory(t1);
  const Vector rest = rig_.rest_shape(motion.p);
  const ElasticTerm<3> elastic(posed_mesh(body_.mesh, rest), make_material<3>(body_.material), 0,
                               body_.mesh.num_elements());
  const Vector force = applied_force(motion);
  const Vector predicted = current.u + h * current.v / c;
  const int nf = static_cast<int>(free_dofs_.size()), n = static_cast<int>(rest.size());
  std::vector<int> free_index(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < nf; ++k) free_index[static_cast<std::size_t>(free_dofs_[k])] = k;

  double magnitude = 0.0;  // of the potential's parts: its round-off level
  auto potential = [&](const Vector& u) {
    const Vector d = u - predicted;
    const double e = elastic.value(rest + u, params_), kinetic = c / (2 * h * h) * d.dot(mass_ * d), work = force.dot(u);
    magnitude = std::abs(e) + kinetic + std::abs(work);
    return kinetic + e - work;
  };
  auto free_part = [&](const Vector& full) {
    Vector y(nf);
    for (int k = 0; k < nf; ++k) y[k] = full[free_dofs_[k]];
    return y;
  };

  Vector u = current.u;  // fixed rows stay 0
  double value = potential(u);
  SparseCholesky solver;
  iterations = 0;
  bool converged = false;
  double last_step = 0.0;
  for (int it = 0; it <= options_.max_newton_iterations; ++it) {
    const Vector inertia = c / (h * h) * (mass_ * (u - predicted));
    Vector internal = Vector::Zero(n);
    elastic.add_gradient(rest + u, params_, internal);
    const Vector gf = free_part(inertia + internal - force);
    const double scale = free_part(inertia).norm() + free_part(internal).norm() + free_part(force).norm();
    // Converged at the tolerance, or at round-off (the last Newton step a few ulps of u).
    if (gf.norm() <= options_.newton_tolerance * (scale + 1e-300) ||
        (it > 0 && last_step <= 1e-13 * (1.0 + u.cwiseAbs().maxCoeff()))) {
      converged = true;
      break;
    }
    if (it == options_.max_newton_iterations) break;
    ++iterations;
    FactorizationResult fr;
    for (HessianMode mode : {HessianMode::exact, HessianMode::projected}) {
      const SparseMatrix k = elastic.hessian(rest + u, params_, mode);
      const SparseMatrix full = SparseMatrix(c / (h * h) * mass_) + k;
      Triplets t;
      for (int col = 0; col < full.outerSize(); ++col)
        for (SparseMatrix::InnerIterator e(full, col); e; ++e) {
          const int a = free_index[static_cast<std::size_t>(e.row())], b = free_index[static_cast<std::size_t>(e.col())];
          if (a >= 0 && b >= 0 && a <= b) t.emplace_back(a, b, e.value());
        }
      SparseMatrix upper(nf, nf);
      upper.setFromTriplets(t.begin(), t.end());
      fr = solver.factorize(upper);
      if (fr.success && fr.positive_definite) break;
    }
    if (!fr.success) {
      message = "moving rest dynamics: factorization failed at t = " + std::to_string(t1) + ": " + fr.message;
      return false;
    }
    const Vector dy = solver.solve(-gf);
    Vector du = Vector::Zero(n);
    for (int k = 0; k < nf; ++k) du[free_dofs_[k]] = dy[k];
    double alpha = 1.0, trial = potential(u + du);
    const double slack = 64 * std::numeric_limits<double>::epsilon() * magnitude;
    while (!(std::isfinite(trial) && trial <= value + 1e-4 * alpha * gf.dot(dy) + slack) && alpha > 1e-8) {
      alpha *= 0.5;
      trial = potential(u + alpha * du);
    }
    if (alpha <= 1e-8 && !(trial <= value)) {
      // At round-off the potential cannot decrease any more: accept when the step is tiny.
      if (dy.norm() <= 1e-12 * (1.0 + u.norm())) {
        converged = true;
        break;
      }
      message = "moving rest dynamics: line search failed at t = " + std::to_string(t1);
      return false;
    }
    u += alpha * du;
    value = trial;
    last_step = alpha * du.cwiseAbs().maxCoeff();
  }
  if (!converged) {
    message = "moving rest dynamics: Newton did not converge at t = " + std::to_string(t1);
    return false;
  }
  next.time = t1;
  next.v = (u - current.u) / h;
  next.u = std::move(u);
  return true;
}

}  // namespace tailor
