// The descent solver of implicit steps (forward/dynamics/descent_solver.hpp), on a Neo-Hookean
// cantilever of 360 tets (enough for the element loop to run in parallel):
//  - the block-Jacobi inverse against the diagonal blocks of the assembled, projected reduced
//    Hessian (ReducedAssembler, written independently of the descent pass);
//  - accepted iterates never raise the incremental potential on a large-deformation step, and
//    without the energy check the same iteration does raise it (the check is not idle);
//  - converged descent reaches Newton's minimizer (the reference: NewtonSolver's step to
//    relative residual 1e-10) over several steps;
//  - iterates are bit-identical for 1 and 2 threads;
//  - Chebyshev acceleration with the estimated rho needs fewer passes than plain descent;
//  - the rho estimate against the spectral radius of the plain iteration matrix I - alpha D^-1 H,
//    computed densely, on a linear material (constant H);
//  - a coupling elimination is refused.
// The vertex-block rule and the device path: descent_kernels_test.cpp.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "../../support/dynamics_fixtures.hpp"
#include "forward/core/assembler.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/dynamics/descent_time_stepper.hpp"

namespace tailor::descent_solver_test {
namespace {

using namespace tailor::testing;

TimeIntegratorOptions step_options(double h) {
  TimeIntegratorOptions o;
  o.time_step = h;
  return o;
}

// Whole-bar upward swing: a velocity growing linearly along the bar to tip_speed at its end.
Vector swing_velocity(const Cantilever& c, double tip_speed) {
  Vector v = Vector::Zero(c.rest.size());
  const double length = c.rest.maxCoeff();
  for (int i = 0; i < c.mesh.num_vertices(); ++i) v[3 * i + 2] = tip_speed * c.rest[3 * i] / length;
  return v;
}

TEST(DescentSolver, BlockInverseMatchesTheAssembledHessiansDiagonalBlocks) {
  Cantilever c(descent_bar_options(24));
  TimeIntegrator integrator(*c.model, step_options(0.01));
  DynamicState s = integrator.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
  integrator.configure_step(s, c.p);
  // A deformed state: the predictor.
  const Vector y = c.model->elimination().restrict_state(integrator.inertia().predictor());
  BlockJacobiPass pass(*c.model, 3);
  DescentEvaluation at;
  pass.evaluate(y, c.p, at, true);
  ReducedAssembler assembler(*c.model);
  SparseMatrix H = assembler.hessian_pattern_matrix();
  double energy = 0;
  Vector g;
  assembler.evaluate(y, c.p, &energy, &g, &H, HessianMode::projected);
  EXPECT_NEAR(at.energy, energy, 1e-12 * std::abs(energy));
  EXPECT_LT((at.gradient - g).norm(), 1e-12 * g.norm());
  const Matrix dense = Matrix(H).selfadjointView<Eigen::Upper>();
  // The clamp fixes whole vertices, so the free unknowns come in threes, vertex by vertex.
  ASSERT_EQ(y.size() % 3, 0);
  const Vector w = Vector::LinSpaced(y.size(), -1.0, 2.0);
  Vector expected(y.size()), direction;
  for (int b = 0; b < y.size() / 3; ++b)
    expected.segment<3>(3 * b) = dense.block<3, 3>(3 * b, 3 * b).ldlt().solve(w.segment<3>(3 * b));
  pass.apply_inverse(at, w, direction);
  EXPECT_LT((direction - expected).norm(), 1e-10 * expected.norm());
}

TEST(DescentSolver, AcceptedIteratesNeverRaiseTheIncrementalPotential) {
  // Large deformation: the bar starts squeezed to half its length (Neo-Hookean stresses of
  // the order of E) and swinging; the first gradient step inverts elements.
  Cantilever c(descent_bar_options(48));
  TimeIntegrator integrator(*c.model, step_options(0.05));
  Vector squeezed = c.rest;
  for (int i = 0; i < c.mesh.num_vertices(); ++i) squeezed[3 * i] *= 0.5;
  const DynamicState start = integrator.initial_state(squeezed, swing_velocity(c, 10.0), c.p);
  DescentOptions o;
  o.max_iterations = 300;
  o.keep_history = true;
  // Bold settings: the unit step (alpha lambda_max(D^-1 H) > 2 here) and a large rho, so that
  // iterates overshoot and the rule must act.
  o.step_length = 1.0;
  o.rho = 0.995;
  auto run = [&](bool energy_check) {
    DescentOptions with = o;
    with.energy_check = energy_check;
    DescentTimeStepper stepper(integrator, with);
    DynamicState s = start;
    const DescentResult r = stepper.step(s, c.p);
    double largest_rise = 0.0, energy = r.initial_energy;
    for (const DescentIteration& it : r.history) {
      if (!it.accepted && energy_check) continue;
      largest_rise = std::max(largest_rise, it.energy - energy);
      energy = it.energy;
    }
    return std::make_tuple(r, largest_rise, (s.x - squeezed).lpNorm<Eigen::Infinity>());
  };
  const auto [checked, rise, moved] = run(true);
  EXPECT_GT(moved, 0.2) << "the step should move the bar far";
  // Rises within the energy's round-off (about 1e-13 of its terms' sizes) are allowed.
  EXPECT_LE(rise, 1e-12 * std::abs(checked.initial_energy)) << "an accepted iterate raised the energy";
  EXPECT_GT(checked.rejections, 0) << "the rule never acted: the scene does not test it";
  EXPECT_LT(checked.final_energy, checked.initial_energy);
  const auto [unchecked, unchecked_rise, unused] = run(false);
  (void)unused;
  EXPECT_GT(unchecked_rise, 1e-6 * std::abs(checked.initial_energy)) << "without the check the same iteration should raise the energy";
  EXPECT_EQ(unchecked.rejections, 0);
}

TEST(DescentSolver, ConvergesToNewtonsMinimizer) {
  // Three steps, each from Newton's state of the step before; the state error of descent
  // falls with its tolerance (the error is about the residual over the smallest stiffness).
  Cantilever c(descent_bar_options(12));
  TimeIntegrator newton(*c.model, step_options(0.02));
  DynamicState reference = newton.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
  auto descend = [&](const DynamicState& from, double tolerance) {
    DescentOptions o;
    o.relative_tolerance = tolerance;
    o.max_iterations = 5000;
    DescentTimeStepper stepper(newton, o);
    DynamicState s = from;
    const DescentResult d = stepper.step(s, c.p);
    EXPECT_TRUE(d.converged()) << d.message;
    return s;
  };
  for (int n = 0; n < 3; ++n) {
    const DynamicState start = reference;
    const DynamicState loose = descend(start, 1e-3), tight = descend(start, 1e-5);
    const NewtonResult r = newton.step(reference, c.p);  // relative tolerance 1e-10
    ASSERT_TRUE(r.converged()) << r.message;
    const double moved = (reference.x - start.x).lpNorm<Eigen::Infinity>();
    const double loose_error = (loose.x - reference.x).lpNorm<Eigen::Infinity>();
    const double tight_error = (tight.x - reference.x).lpNorm<Eigen::Infinity>();
    std::printf("step %d: moved %.3e, state error at tolerance 1e-3 %.3e, 1e-5 %.3e\n", n + 1, moved,
                loose_error, tight_error);
    EXPECT_LT(tight_error, 1e-4 * moved);
    EXPECT_LT(tight_error, 0.1 * loose_error);
    EXPECT_LT((tight.v - reference.v).lpNorm<Eigen::Infinity>(), 1e-4 * reference.v.lpNorm<Eigen::Infinity>());
  }
}

TEST(DescentSolver, IteratesAreTheSameForOneAndTwoThreads) {
  Cantilever c(descent_bar_options(48));
  ASSERT_GT(c.num_elements(), 256);  // the element loop's threshold for running in parallel
  const int saved = omp_get_max_threads();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    TimeIntegrator integrator(*c.model, step_options(0.02));
    DynamicState s = integrator.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
    DescentOptions o;
    o.max_iterations = 60;
    DescentTimeStepper stepper(integrator, o);
    std::vector<int> iterations;
    for (int n = 0; n < 3; ++n) iterations.push_back(stepper.step(s, c.p).iterations);
    return std::make_pair(s.x, iterations);
  };
  const auto one = run(1);
  const auto two = run(2);
  omp_set_num_threads(saved);
  EXPECT_EQ(one.second, two.second);
  EXPECT_EQ((one.first - two.first).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DescentSolver, ChebyshevAccelerationNeedsFewerPasses) {
  Cantilever c(descent_bar_options(12));
  TimeIntegrator integrator(*c.model, step_options(0.02));
  const DynamicState start = integrator.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
  auto passes = [&](std::optional<double> rho) {
    DescentOptions o;
    o.relative_tolerance = 1e-6;
    o.max_iterations = 20000;
    o.rho = rho;
    DescentTimeStepper stepper(integrator, o);
    DynamicState s = start;
    const DescentResult r = stepper.step(s, c.p);
    EXPECT_TRUE(r.converged()) << r.message;
    return r.iterations;
  };
  const int plain = passes(0.0), accelerated = passes(std::nullopt);
  std::printf("passes to 1e-6: plain %d, Chebyshev with estimated rho %d\n", plain, accelerated);
  EXPECT_LT(3 * accelerated, plain);
}

TEST(DescentSolver, RhoEstimateAgainstTheIterationMatrix) {
  // Linear material: H is constant, so the plain iteration is the linear map I - alpha D^-1 H
  // whose spectral radius the estimate aims at.
  Cantilever c(descent_bar_options(12, MaterialKind::linear));
  TimeIntegrator integrator(*c.model, step_options(0.02));
  DynamicState s = integrator.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
  DescentOptions o;
  o.max_iterations = 200;
  DescentTimeStepper stepper(integrator, o);
  stepper.step(s, c.p);
  ASSERT_TRUE(stepper.solver().spectral_radius().has_value());
  const double estimate = *stepper.solver().spectral_radius();
  // Dense reference at the step's settings: with D^-1 = C C^T (Cholesky), D^-1 H has the
  // spectrum of the symmetric C^T H C (no general eigen solver: it costs compile time).
  ReducedAssembler assembler(*c.model);
  SparseMatrix H = assembler.hessian_pattern_matrix();
  assembler.evaluate(s.y, c.p, nullptr, nullptr, &H, HessianMode::projected);
  const Matrix dense = Matrix(H).selfadjointView<Eigen::Upper>();
  DescentEvaluation at;
  stepper.solver().pass().evaluate(s.y, c.p, at, true);
  const Eigen::Index n = dense.rows();
  Matrix Dinv(n, n);
  Vector column;
  for (Eigen::Index j = 0; j < n; ++j) {
    stepper.solver().pass().apply_inverse(at, Vector::Unit(n, j), column);
    Dinv.col(j) = column;
  }
  const Matrix C = Eigen::LLT<Matrix>(Dinv.selfadjointView<Eigen::Upper>()).matrixL();
  const Eigen::VectorXd lambda = symmetric_eigenvalues(C.transpose() * dense * C);
  const double alpha = stepper.solver().step_length();
  double radius = 0;
  for (const double l : lambda) radius = std::max(radius, std::abs(1.0 - alpha * l));
  std::printf("rho: estimate %.5f, spectral radius of I - alpha D^-1 H %.5f\n", estimate, radius);
  EXPECT_LE(estimate, radius + 1e-3);
  EXPECT_GT(estimate, radius - 0.1 * (1.0 - radius) - 0.02);
}

TEST(DescentSolver, RefusesCouplingConstraints) {
  Cantilever c(descent_bar_options(12));
  const int n = c.model->num_dofs();
  SparseMatrix S(n, n - 1);
  std::vector<Triplet> t;
  for (int i = 0; i < n - 1; ++i) t.emplace_back(i, i, 1.0);
  t.emplace_back(n - 1, 0, 1.0);  // the last DOF follows the first: periodic-like
  S.setFromTriplets(t.begin(), t.end());
  c.model->set_elimination(Elimination(c.rest, S));
  EXPECT_THROW(BlockJacobiPass(*c.model, 3), std::invalid_argument);
}


}  // namespace
}  // namespace tailor::descent_solver_test
