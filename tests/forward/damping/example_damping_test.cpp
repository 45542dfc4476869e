// Example-based damping (Xu & Barbic 2017): the scaled damping is dissipative for every
// gamma >= 0, reduces to Rayleigh damping at gamma = 1, damps motion along an example gamma
// times as strongly, and its derivatives (state, Rayleigh and curve parameters, the low-rank
// Hessian part) pass the derivative checks, which reject a corrupted term.
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "damping_fixture.hpp"
#include "forward/core/symmetric_eigen.hpp"

namespace tailor::example_damping_test {
namespace {

using namespace tailor::testing;

// The dense dissipation matrix C^ (pattern part plus low-rank part) of a small model.
Matrix dense_damping_matrix(const ExampleDamping& term, const Vector& p) {
  const Eigen::Index n = term.examples().rows();
  Matrix C = Matrix::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    Vector e = Vector::Zero(n), g = Vector::Zero(n);
    e[j] = 1.0;
    EnergyRequest r;
    r.gradient = &g;
    term.evaluate_dissipation(e, p, r);  // D is quadratic in v: its gradient at e_j is column j
    C.col(j) = g;
  }
  return C;
}

double dissipation(const DampingTerm& term, const Vector& v, const Vector& p) {
  double value = 0.0;
  EnergyRequest r;
  r.value = &value;
  term.evaluate_dissipation(v, p, r);
  return value;
}

TEST(ExampleDamping, DissipatedPowerIsNeverNegative) {
  DampedBar d(constant_curves(3), /*random_third=*/true);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 5.0);
  const Eigen::Index n = d.p.size();
  (void)n;
  double min_power = 1e300, min_eigen_ratio = 1e300;
  for (int trial = 0; trial < 60; ++trial) {
    for (int i = 0; i < 3; ++i) {
      double g = u(rng);
      if (trial % 5 == i) g = 0.0;  // exact zeros: the boundary of the admissible set
      d.set_scale(i, g);
    }
    const Vector v = random_vector(d.bar.model->num_dofs(), 100 + trial, 1.0);
    Vector grad = Vector::Zero(v.size());
    EnergyRequest r;
    r.gradient = &grad;
    d.term().evaluate_dissipation(v, d.p, r);
    const double power = v.dot(grad);  // v^T C^ v = 2 D(v)
    EXPECT_NEAR(power, 2.0 * dissipation(d.term(), v, d.p), 1e-10 * std::abs(power));
    min_power = std::min(min_power, power);
    if (trial < 10) {
      const Matrix C = dense_damping_matrix(d.term(), d.p);
      EXPECT_LT((C - C.transpose()).norm(), 1e-12 * C.norm());
      const Vector lambda = symmetric_eigenvalues(0.5 * (C + C.transpose()));
      min_eigen_ratio = std::min(min_eigen_ratio, lambda.minCoeff() / lambda.maxCoeff());
    }
  }
  std::printf("smallest power %.3e, smallest eigenvalue / largest %.3e\n", min_power, min_eigen_ratio);
  EXPECT_GE(min_power, 0.0);
  EXPECT_GE(min_eigen_ratio, -1e-12);
}

TEST(ExampleDamping, ReducesToRayleighAndScalesMotionAlongExamples) {
  DampedBar d(constant_curves(3), true);
  const RayleighDamping& rayleigh = d.term().base();
  const Vector v = random_vector(d.bar.model->num_dofs(), 3, 1.0);
  for (int i = 0; i < 3; ++i) d.set_scale(i, 1.0);
  EXPECT_NEAR(dissipation(d.term(), v, d.p), dissipation(rayleigh, v, d.p),
              1e-12 * dissipation(rayleigh, v, d.p));
  const double gammas[3] = {0.1, 3.0, 0.0};
  for (int i = 0; i < 3; ++i) d.set_scale(i, gammas[i]);
  for (int i = 0; i < 3; ++i) {
    const Vector u = d.term().examples().col(i);
    EXPECT_NEAR(dissipation(d.term(), u, d.p), gammas[i] * dissipation(rayleigh, u, d.p),
                1e-12 * dissipation(rayleigh, u, d.p));
  }
  // Velocities M-orthogonal to every example are damped exactly like Rayleigh's when the
  // examples are decoupled... in general they keep their own block: check v_perp^T C^ v_perp.
  const Matrix& W = d.term().mass_examples();
  const Matrix& U = d.term().examples();
  const Vector v_perp = v - U * (W.transpose() * v);
  EXPECT_NEAR(dissipation(d.term(), v_perp, d.p), dissipation(rayleigh, v_perp, d.p),
              1e-12 * dissipation(rayleigh, v_perp, d.p));
}

void expect_passes(const EnergyTerm& term, const Vector& x, const Vector& p) {
  const EnergyTermCheck check = check_energy_term(term, x, p);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
}

TEST(ExampleDamping, DerivativeChecksLinearScales) {
  DampedBar d(constant_curves(3), true);
  d.set_scale(0, 0.1);
  d.set_scale(1, 3.0);
  d.set_scale(2, 0.7);
  const Vector x = d.bar.rest + random_vector(d.bar.rest.size(), 9, 0.05);
  d.term().set_velocity_map(0.01, d.bar.rest + random_vector(d.bar.rest.size(), 11, 0.05));
  expect_passes(d.term(), x, d.p);
}

std::vector<DampingCurve> rising_curves() {
  DampingCurve c;
  c.knots = Vector(4);
  c.knots << 0.0, 0.05, 0.1, 0.2;
  return {c, c};
}

TEST(ExampleDamping, DerivativeChecksNonlinearCurves) {
  DampedBar d(rising_curves());
  Vector values(4);
  values << 0.5, 1.0, 2.5, 4.0;
  d.set_controls(0, values);
  d.set_controls(1, 0.5 * values);
  Vector chi(2);
  chi << 0.07, 0.13;  // inside the second and third segments
  d.term().set_amplitudes(chi);
  EXPECT_NEAR(d.term().scale(0, d.p), d.term().curve(0, d.p, 0.07), 1e-15);
  const Vector x = d.bar.rest + random_vector(d.bar.rest.size(), 19, 0.05);
  d.term().set_velocity_map(0.02, d.bar.rest);
  expect_passes(d.term(), x, d.p);
}

// Forwards to an example damping term but drops its low-rank Hessian part.
class WithoutLowRank final : public DampingTerm {
 public:
  explicit WithoutLowRank(const ExampleDamping& inner) : inner_(inner) {}
  std::string name() const override { return "corrupted_example_damping"; }
  void evaluate_dissipation(const Vector& v, const Vector& p, const EnergyRequest& r) const override {
    inner_.evaluate_dissipation(v, p, r);
  }
  void dissipation_pattern(HessianPattern& pattern) const override { inner_.dissipation_pattern(pattern); }
  void add_dissipation_param_gradient(const Vector& v, const Vector& p, Vector& g) const override {
    inner_.add_dissipation_param_gradient(v, p, g);
  }
  void add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                             Vector& g) const override {
    inner_.add_dissipation_mixed_transpose_times(v, p, w, g);
  }

 private:
  const ExampleDamping& inner_;
};

TEST(ExampleDamping, CorruptedHessianIsRejected) {
  DampedBar d(constant_curves(2));
  d.set_scale(0, 0.1);
  d.set_scale(1, 3.0);
  WithoutLowRank corrupted(d.term());
  corrupted.set_velocity_map(0.01, d.bar.rest);
  const Vector x = d.bar.rest + random_vector(d.bar.rest.size(), 23, 0.05);
  const EnergyTermCheck check = check_energy_term(corrupted, x, d.p);
  EXPECT_FALSE(check.passed()) << check.table();
  for (const auto& c : check.checks)
    if (c.quantity == "hessian") {
      EXPECT_FALSE(c.passed);
    }
}

TEST(ExampleDamping, AmplitudeIsConstantOverAHarmonicCycleAndDifferentiable) {
  DampedBar d(rising_curves());
  const ExampleDamping& t = d.term();
  const Vector u = t.examples().col(1);
  const double omega = t.frequencies()[1], a = u.cwiseAbs().maxCoeff(), A = 0.3;
  for (int k = 0; k < 8; ++k) {
    const double phase = 0.7 * k;
    const Vector x = d.bar.rest + A * std::cos(phase) * u, v = -A * omega * std::sin(phase) * u;
    EXPECT_NEAR(t.amplitude(1, x, v), A * a, 1e-7);  // the largest nodal displacement amplitude
    EXPECT_NEAR(t.amplitude(0, x, v), 0.0, 1e-7);
  }
  const Vector x = d.bar.rest + random_vector(d.bar.rest.size(), 29, 0.1);
  const Vector v = random_vector(d.bar.rest.size(), 31, 1.0);
  Vector gx, gv;
  t.amplitude(0, x, v, &gx, &gv);
  const Vector dx = random_vector(x.size(), 37, 0.1), dv = random_vector(x.size(), 41, 1.0);
  DerivativeCheckOptions o;
  const auto f = [&](double h) { return Vector::Constant(1, t.amplitude(0, x + h * dx, v + h * dv)); };
  const DerivativeCheck c =
      check_directional_derivative("amplitude", f, Vector::Constant(1, gx.dot(dx) + gv.dot(dv)), o);
  EXPECT_TRUE(c.passed) << c.message;
}

TEST(ExampleDamping, ExamplesDoNotFollowRotations) {
  // Documented behaviour: examples live in the rest frame. Example 0 bends the bar in z, example
  // 1 in y; the field of example 0 rotated by 90 degrees about the bar's axis is seen entirely
  // as example 1, and an infinitesimal rigid rotation about the axis is damped exactly like
  // Rayleigh (it is M-orthogonal to both bending examples).
  DampedBar d(constant_curves(2));
  d.set_scale(0, 0.1);
  d.set_scale(1, 3.0);
  const ExampleDamping& t = d.term();
  const Vector u0 = t.examples().col(0);
  Vector rotated = Vector::Zero(u0.size());
  for (Eigen::Index v = 0; v < u0.size() / 3; ++v) {  // R e_z = -e_y, R e_y = e_z
    rotated[3 * v + 1] = -u0[3 * v + 2];
    rotated[3 * v + 2] = u0[3 * v + 1];
  }
  const Vector zero = Vector::Zero(u0.size());
  EXPECT_NEAR(t.amplitude(0, d.bar.rest + 0.2 * rotated, zero), 0.0, 1e-6);
  EXPECT_GT(t.amplitude(1, d.bar.rest + 0.2 * rotated, zero), 0.1 * 0.2 * u0.cwiseAbs().maxCoeff());
  Vector spin = Vector::Zero(u0.size());
  for (int v = 0; v < d.bar.mesh.num_vertices(); ++v) {
    spin[3 * v + 1] = -(d.bar.mesh.rest_positions(v, 2) - 0.5);
    spin[3 * v + 2] = d.bar.mesh.rest_positions(v, 1) - 0.5;
  }
  EXPECT_NEAR(dissipation(t, spin, d.p), dissipation(t.base(), spin, d.p),
              1e-12 * dissipation(t.base(), spin, d.p));
}

TEST(ExampleDamping, NewtonStepIsExactWithTheLowRankHessian) {
  // Linear elasticity + quadratic damping: each step's potential is quadratic, so one Newton
  // step with the exact Hessian (sparse factor + Woodbury) solves it.
  DampedBar d(constant_curves(3), true);
  d.set_scale(0, 0.1);
  d.set_scale(1, 5.0);
  d.set_scale(2, 2.0);
  d.p[d.damping.alpha_offset] = 2.0;
  d.p[d.damping.beta_offset] = 0.05;
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark}) {
    TimeIntegratorOptions o;
    o.scheme = scheme;
    o.time_step = 0.05;
    TimeIntegrator integrator(*d.bar.model, o);
    DynamicState s = integrator.initial_state(d.bar.rest,
                                              d.bar.model->elimination().expand_direction(random_vector(
                                                  d.bar.model->elimination().num_free(), 43, 1.0)),
                                              d.p);
    for (int k = 0; k < 3; ++k) {
      const NewtonResult r = integrator.step(s, d.p);
      ASSERT_TRUE(r.converged()) << r.report();
      EXPECT_LE(r.iterations, 2) << r.report();
    }
  }
}

}  // namespace
}  // namespace tailor::example_damping_test
