// Example-based damping has a low-rank Hessian part (a Woodbury update on CHOLMOD's factor),
// which a LinearSolver (NewtonOptions::linear_solver, e.g. PETSc) is not given: both the time
// steps and the transient adjoint's backward solves refuse it with a clear message instead of
// solving a different system.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>

#include "adjoint/transient_functional.hpp"
#include "damping_fixture.hpp"

namespace tailor::linear_solver_refusal_test {
namespace {

using namespace tailor::testing;

// Eigen's LDL^T: solves exactly what it is given (the sparse part only).
class SparseOnlySolver final : public LinearSolver {
 public:
  std::string name() const override { return "sparse-only"; }
  bool setup(const SparseMatrix& upper, std::string& message) override {
    ldlt_.compute(upper);
    if (ldlt_.info() != Eigen::Success) message = "not positive definite";
    return ldlt_.info() == Eigen::Success;
  }
  LinearSolveStats solve(const Vector& b, double relative_tolerance, Vector& x) override {
    x = ldlt_.solve(b);
    LinearSolveStats s;
    s.converged = x.allFinite();
    s.relative_tolerance = relative_tolerance;
    return s;
  }

 private:
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Upper> ldlt_;
};

TEST(LinearSolverRefusal, LowRankDampingIsRefusedByStepsAndTransientAdjoint) {
  DampedBar d(constant_curves(2));
  d.set_scale(0, 0.5);
  d.set_scale(1, 2.0);
  TimeIntegratorOptions o;
  o.scheme = TimeScheme::newmark;
  o.time_step = 0.05;
  const Vector v0 = d.bar.model->elimination().expand_direction(
      random_vector(d.bar.model->elimination().num_free(), 43, 1.0));

  // A time step on the solver fails and says why.
  TimeIntegratorOptions on_solver = o;
  on_solver.newton.linear_solver = std::make_shared<SparseOnlySolver>();
  TimeIntegrator stepping(*d.bar.model, on_solver);
  DynamicState s = stepping.initial_state(d.bar.rest, v0, d.p);
  const NewtonResult r = stepping.step(s, d.p);
  EXPECT_FALSE(r.converged());
  EXPECT_NE(r.message.find("does not support terms with low-rank Hessian parts"), std::string::npos)
      << r.message;

  // Forward on CHOLMOD, then the backward pass on the solver: the adjoint refuses too.
  TimeIntegrator integrator(*d.bar.model, o);
  const ParameterizationPtr map = embed_blocks(d.p, {{d.damping.alpha_offset, identity_map(2)}});
  Vector z(2);
  z << d.p[d.damping.alpha_offset], d.p[d.damping.beta_offset];
  Matrix target = Matrix::Zero(d.bar.tip_vertices.size(), 3);
  auto objective = std::make_shared<KeyframeTargets>(3, d.bar.tip_vertices, TrajectoryQuantity::velocity,
                                                     std::vector<Keyframe>{{3, target, 1.0}});
  TransientFunctionalOptions options;
  options.steps = 3;
  TransientFunctional functional(integrator, map, objective, d.bar.rest, v0, options);
  Vector gradient;
  functional.value_and_gradient(z, gradient);  // CHOLMOD with the Woodbury update
  EXPECT_TRUE(gradient.allFinite());
  integrator.newton().options().linear_solver = std::make_shared<SparseOnlySolver>();
  try {
    functional.value_and_gradient(z, gradient);  // the cached forward pass, then backward
    ADD_FAILURE() << "the transient adjoint solved without the low-rank part";
  } catch (const EvaluationError& e) {
    EXPECT_NE(
        std::string(e.what()).find("transient adjoint: the linear solver 'sparse-only' does not support "
                                   "terms with low-rank Hessian parts (step 3)"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tailor::linear_solver_refusal_test
