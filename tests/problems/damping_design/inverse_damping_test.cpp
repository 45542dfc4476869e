// Inverse damping design through the time-dependent adjoint: the control values of the
// damping curves gamma_i(chi) of two examples (a rising curve on example 0, a constant on
// example 1) are the design. Taylor tests (rate >= 1.9) for each target type: a recorded
// trajectory (tip positions over time), the amplitude lost per oscillation cycle along each
// example, and a decay rate per example (both as example-amplitude keyframes); and recovery
// of the curves used to synthesize a trajectory from a start off by a factor 2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../../forward/damping/damping_fixture.hpp"
#include "adjoint/taylor_test.hpp"
#include "adjoint/transient_functional.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor::inverse_damping_test {
namespace {

using namespace tailor::testing;

struct InverseDamping {
  static CantileverOptions bar_options() {
    CantileverOptions o;
    o.material = MaterialKind::linear;
    o.youngs_modulus = 1e5;
    return o;
  }
  static std::vector<DampingCurve> curves() {
    DampingCurve rising, constant;
    rising.knots = Vector(3);
    rising.knots << 0.005, 0.015, 0.03;  // tip amplitudes [length] the motion passes through
    return {rising, constant};
  }
  DampedBar d{curves(), false, bar_options()};
  Vector truth = (Vector(4) << 0.5, 1.5, 3.0, 2.0).finished();
  ParameterizationPtr map;
  Vector x0, v0;
  int steps = 120;
  double time_step = 0.01;

  explicit InverseDamping(double amplitude = 0.04) {
    d.p[d.damping.alpha_offset] = 2.0;
    d.p[d.damping.beta_offset] = 1e-4;
    map = embed_blocks(d.p, {{d.damping.curve_offset, identity_map(4)}});
    const Matrix& U = d.term().examples();
    x0 = d.bar.rest + amplitude / U.col(0).cwiseAbs().maxCoeff() * U.col(0) +
         0.01 / U.col(1).cwiseAbs().maxCoeff() * U.col(1);
    v0 = Vector::Zero(x0.size());
  }
  TimeIntegratorOptions integrator_options(TimeScheme scheme) const {
    TimeIntegratorOptions o;
    o.scheme = scheme;
    o.time_step = time_step;
    o.newton.relative_tolerance = 1e-12;
    return o;
  }
  TransientFunctionalOptions functional_options() const {
    TransientFunctionalOptions o;
    o.steps = steps;
    return o;
  }
  // Tip positions at every second step, simulated with the given controls.
  TrajectoryObjectivePtr recorded_trajectory(const Vector& controls) {
    TimeIntegrator integrator(*d.bar.model, integrator_options(TimeScheme::newmark));
    const Vector p = map->apply(controls);
    DynamicState s = integrator.initial_state(x0, v0, p);
    std::vector<Keyframe> frames;
    for (int k = 1; k <= steps; ++k) {
      EXPECT_TRUE(integrator.step(s, p).converged());
      if (k % 2) continue;
      Matrix t(d.bar.tip_vertices.size(), 3);
      for (std::size_t i = 0; i < d.bar.tip_vertices.size(); ++i)
        t.row(static_cast<Eigen::Index>(i)) = s.x.segment(3 * d.bar.tip_vertices[i], 3).transpose();
      frames.push_back({k, t, 1e4});
    }
    return std::make_shared<KeyframeTargets>(3, d.bar.tip_vertices, TrajectoryQuantity::position, frames);
  }
  // Example amplitudes q_i = u_i^T M (x - X) at whole periods of example 0 with targets
  // q_i(0) * factor_i(k) (per-cycle loss: (1 - loss)^k; decay rate: exp(-sigma t_k)).
  TrajectoryObjectivePtr example_amplitudes(const std::function<double(int example, double time)>& factor) {
    const ExampleDamping& t = d.term();
    const double period = 2.0 * M_PI / t.frequencies()[0];
    const Vector q0 = t.mass_examples().transpose() * (x0 - d.bar.rest);
    std::vector<AmplitudeKeyframe> frames;
    for (int k = 1;; ++k) {
      const int step = static_cast<int>(std::lround(k * period / time_step));
      if (step > steps) break;
      Vector target(2);
      for (int i = 0; i < 2; ++i) target[i] = q0[i] * factor(i, step * time_step);
      frames.push_back({step, target, 1e2});
    }
    return std::make_shared<ModeAmplitudes>(t.examples(), d.bar.terms.inertia->mass().matrix(d.p), d.bar.rest,
                                            frames);
  }
  void expect_taylor(TrajectoryObjectivePtr objective, TimeScheme scheme, const char* label) {
    TimeIntegrator integrator(*d.bar.model, integrator_options(scheme));
    TransientFunctional f(integrator, map, objective, x0, v0, functional_options());
    const TaylorTestResult r = taylor_test(f, 2.0 * truth);
    std::printf("%s (%s):\n%s", label, to_string(scheme).c_str(), r.table().c_str());
    EXPECT_TRUE(r.passed()) << r.table();
    EXPECT_GE(r.rate1, 1.9);
  }
};

TEST(InverseDamping, TaylorTestRecordedTrajectory) {
  InverseDamping problem;
  problem.expect_taylor(problem.recorded_trajectory(problem.truth), TimeScheme::newmark, "trajectory");
}

TEST(InverseDamping, TaylorTestLossPerCycle) {
  InverseDamping problem;
  const double loss[2] = {0.3, 0.2};
  const double period = 2.0 * M_PI / problem.d.term().frequencies()[0];
  problem.expect_taylor(
      problem.example_amplitudes([&](int i, double t) { return std::pow(1.0 - loss[i], t / period); }),
      TimeScheme::bdf2, "loss per cycle");
}

TEST(InverseDamping, TaylorTestDecayRate) {
  InverseDamping problem;
  const double rate[2] = {1.5, 1.0};  // [1/time]
  problem.expect_taylor(problem.example_amplitudes([&](int i, double t) { return std::exp(-rate[i] * t); }),
                        TimeScheme::implicit_euler, "decay rate");
}

TEST(InverseDamping, TaylorTestWithRayleighAndInitialState) {
  // Rayleigh alpha, beta and the initial positions and velocities join the design: the Newmark start force
  // g_0 then depends on the design through the lagged scales at (x_0, v_0) too (an initial
  // amplitude inside the knot range, where the curve's slope is not zero).
  InverseDamping problem(0.012);
  const int np = static_cast<int>(problem.d.p.size()), n = static_cast<int>(problem.x0.size());
  Vector base = Vector::Zero(np + 2 * n);
  base.head(np) = problem.d.p;
  const ParameterizationPtr map = embed_blocks(base, {{problem.d.damping.curve_offset, identity_map(4)},
                                                      {problem.d.damping.alpha_offset, identity_map(2)},
                                                      {np, identity_map(2 * n)}});
  const Vector v0 = 20.0 * (problem.x0 - problem.d.bar.rest);  // strong initial damping force
  Vector z(4 + 2 + 2 * n);
  z << 2.0 * problem.truth, 20.0, 1e-4, problem.x0, v0;
  TimeIntegrator integrator(*problem.d.bar.model, problem.integrator_options(TimeScheme::newmark));
  TransientFunctionalOptions o = problem.functional_options();
  o.design_initial_positions = o.design_initial_velocities = true;
  TransientFunctional f(integrator, map, problem.recorded_trajectory(problem.truth), problem.x0, v0, o);
  const TaylorTestResult r = taylor_test(f, z);
  std::printf("trajectory, design with alpha, beta, x0, v0 (newmark):\n%s", r.table().c_str());
  EXPECT_TRUE(r.passed()) << r.table();
  EXPECT_GE(r.rate1, 1.9);
}

TEST(InverseDamping, RecoversCurvesFromATrajectory) {
  InverseDamping problem;
  TimeIntegrator integrator(*problem.d.bar.model, problem.integrator_options(TimeScheme::newmark));
  TransientFunctional f(integrator, problem.map, problem.recorded_trajectory(problem.truth), problem.x0,
                        problem.v0, problem.functional_options());
  // The motion must pass through every knot for every control value to be identifiable.
  double largest = 0.0, smallest = 1e300;
  {
    Vector g;
    f.value_and_gradient(problem.truth, g);
    for (const DynamicState& s : f.stored_states()) {
      const double chi = problem.d.term().amplitude(0, s.x, s.v);
      largest = std::max(largest, chi), smallest = std::min(smallest, chi);
    }
  }
  std::printf("example 0 amplitude from %.4f down to %.4f\n", largest, smallest);
  EXPECT_GT(largest, 0.03);
  EXPECT_LT(smallest, 0.005);
  OptimizerOptions o;
  o.backend = OptimizerBackend::nlopt_lbfgs;
  o.max_iterations = 200;
  o.gradient_tolerance = 1e-9;
  const Vector start = 2.0 * problem.truth;
  const OptimizerResult r = minimize(f, start, Bounds{Vector::Zero(4), Vector()}, {}, o);
  std::printf(
      "%s\nstart %s\nfound %s\ntruth %s\n", r.report().c_str(), "2 x truth",
      ::testing::PrintToString(std::vector<double>(r.z.data(), r.z.data() + 4)).c_str(),
      ::testing::PrintToString(std::vector<double>(problem.truth.data(), problem.truth.data() + 4)).c_str());
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(r.z[k] / problem.truth[k], 1.0, 0.05) << "control " << k;
}

}  // namespace
}  // namespace tailor::inverse_damping_test
