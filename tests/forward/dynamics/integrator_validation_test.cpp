// Validation of the time integrators against closed forms for a linear oscillator and
// against the cantilever's own modal analysis (K phi = lambda M phi):
//  - convergence orders (implicit Euler 1, Newmark 2, BDF2 2) against q(t) = A cos(omega t);
//  - implicit Euler's numerical damping per step, 1/sqrt(1 + (omega h)^2), vs h;
//  - Newmark's energy drift on an undamped cantilever (linear and Neo-Hookean, 1000 steps);
//  - the free-vibration period of a Neo-Hookean cantilever vs 2 pi / omega_1, with Newmark's
//    known period elongation omega~ h = 2 atan(omega h / 2);
//  - the Rayleigh damping ratio of a mode, alpha/(2 omega) + beta omega/2, by log decrement;
//  - prescribed motions, and reduction by projection (Elimination::general with modes).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "../../support/modal_fixtures.hpp"

namespace tailor::integrator_validation_test {
namespace {

using namespace tailor::testing;
constexpr double kPi = 3.14159265358979323846;

struct Trajectory {
  std::vector<DynamicState> states;
  std::vector<double> energy;  // kinetic + potential
};

Trajectory simulate(Cantilever& c, const Vector& p, TimeScheme scheme, double h, int steps, const Vector& x0,
                    const Vector& v0) {
  TimeIntegratorOptions o;
  o.scheme = scheme;
  o.time_step = h;
  if (std::getenv("TAILOR_DEBUG")) o.newton.progress = &std::cout;
  TimeIntegrator integrator(*c.model, o);
  Trajectory run;
  DynamicState s = integrator.initial_state(x0, v0, p);
  run.states.push_back(s);
  run.energy.push_back(integrator.kinetic_energy(s.v, p) + integrator.potential_energy(s.x, p));
  for (int n = 0; n < steps; ++n) {
    const NewtonResult r = integrator.step(s, p);
    if (!r.converged()) {
      std::cout << r.report();
      throw std::runtime_error("step " + std::to_string(n) + ": " + r.message);
    }
    run.states.push_back(s);
    run.energy.push_back(integrator.kinetic_energy(s.v, p) + integrator.potential_energy(s.x, p));
  }
  return run;
}

CantileverOptions linear_options() {
  CantileverOptions o;
  o.material = MaterialKind::linear;
  return o;
}

TEST(Integrators, ModesSolveTheGeneralizedEigenproblem) {
  // Guards the reference itself: K phi = omega^2 M phi on the free DOFs (the dense path once
  // solved K M phi = lambda phi instead).
  Cantilever c(linear_options());
  const CantileverModes modes = cantilever_modes(c, c.p, 2);
  const SparseMatrix K = c.model->terms()[0]->hessian(c.rest, c.p, HessianMode::exact);
  const SparseMatrix& S = c.model->elimination().basis();
  for (int k = 0; k < 2; ++k) {
    const Vector Kphi = S.transpose() * (K * modes.shapes.col(k));
    const Vector Mphi = S.transpose() * (modes.mass * modes.shapes.col(k));
    EXPECT_LT((Kphi - modes.omega[k] * modes.omega[k] * Mphi).norm(), 1e-9 * Kphi.norm());
  }
}

TEST(Integrators, ConvergenceOrdersOnAModalOscillator) {
  Cantilever c(linear_options());
  const CantileverModes modes = cantilever_modes(c, c.p, 1);
  const double omega = modes.omega[0], period = 2 * kPi / omega, amplitude = 0.01;
  const Vector x0 = c.rest + amplitude * modes.shapes.col(0);
  std::printf(
      "scheme           h=T/16     T/32       T/64   (error of (omega q, q') at t = T/4, relative)  order\n");
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark, TimeScheme::bdf2}) {
    std::vector<double> errors;
    for (int per_period : {16, 32, 64}) {
      // Error of the phase-space point (omega q, q') against A (cos, -sin)(omega t) at t = T/4:
      // it contains both the amplitude and the phase error.
      const Trajectory run =
          simulate(c, c.p, scheme, period / per_period, per_period / 4, x0, Vector::Zero(x0.size()));
      const double q = modal_coordinate(modes, 0, run.states.back().x - c.rest);
      const double qdot = modal_coordinate(modes, 0, run.states.back().v);
      errors.push_back(std::hypot(omega * q, qdot + amplitude * omega) / (amplitude * omega));
    }
    const double order = std::log2(errors[1] / errors[2]);
    std::printf("%-15s %.3e %.3e %.3e  %.2f\n", to_string(scheme).c_str(), errors[0], errors[1], errors[2],
                order);
    EXPECT_NEAR(order, scheme == TimeScheme::implicit_euler ? 1.0 : 2.0, 0.25) << to_string(scheme);
  }
}

TEST(Integrators, ImplicitEulerNumericalDampingMatchesClosedForm) {
  // Implicit Euler on q'' = -omega^2 q: (omega q, q') is multiplied by a rotation scaled by
  // 1/sqrt(1 + (omega h)^2) per step, so sqrt(omega^2 q^2 + q'^2) decays exactly by that.
  Cantilever c(linear_options());
  const CantileverModes modes = cantilever_modes(c, c.p, 1);
  const double omega = modes.omega[0], period = 2 * kPi / omega;
  const Vector x0 = c.rest + 0.01 * modes.shapes.col(0);
  std::printf("h/T      omega*h   ratio/step measured  closed form   decay/period measured  closed form\n");
  for (int per_period : {10, 20, 40, 80}) {
    const double h = period / per_period;
    const Trajectory run =
        simulate(c, c.p, TimeScheme::implicit_euler, h, per_period, x0, Vector::Zero(x0.size()));
    auto norm = [&](const DynamicState& s) {
      return std::hypot(omega * modal_coordinate(modes, 0, s.x - c.rest), modal_coordinate(modes, 0, s.v));
    };
    const double measured = std::pow(norm(run.states.back()) / norm(run.states.front()), 1.0 / per_period);
    const double closed = 1.0 / std::sqrt(1.0 + std::pow(omega * h, 2));
    std::printf("1/%-5d  %.4f    %.8f          %.8f    %.6f              %.6f\n", per_period, omega * h,
                measured, closed, std::pow(measured, per_period), std::pow(closed, per_period));
    EXPECT_NEAR(measured, closed, 1e-7 * closed);
  }
}

double max_relative_drift(const std::vector<double>& energy) {
  double drift = 0.0;
  for (double e : energy) drift = std::max(drift, std::abs(e - energy.front()) / std::abs(energy.front()));
  return drift;
}

TEST(Integrators, NewmarkConservesEnergyOfAnUndampedCantilever) {
  // The trapezoidal rule conserves 1/2 v^T M v + 1/2 u^T K u exactly for linear elasticity and
  // only approximately for Neo-Hookean (bound 2e-2 at h = T1/40); implicit Euler loses nearly all.
  for (MaterialKind kind : {MaterialKind::linear, MaterialKind::neo_hookean}) {
    CantileverOptions o;
    o.material = kind;
    Cantilever c(o);
    const CantileverModes modes = cantilever_modes(c, c.p, 2);
    const double period = 2 * kPi / modes.omega[0], h = period / 40;
    // A visible swing: tip displacement ~0.25 of the bar's thickness, two modes mixed.
    const Vector x0 = c.rest + 0.2 * modes.shapes.col(0) / modes.shapes.col(0).cwiseAbs().maxCoeff() +
                      0.05 * modes.shapes.col(1) / modes.shapes.col(1).cwiseAbs().maxCoeff();
    const Trajectory newmark = simulate(c, c.p, TimeScheme::newmark, h, 1000, x0, Vector::Zero(x0.size()));
    const Trajectory euler =
        simulate(c, c.p, TimeScheme::implicit_euler, h, 1000, x0, Vector::Zero(x0.size()));
    const double drift = max_relative_drift(newmark.energy);
    const double first_half = max_relative_drift({newmark.energy.begin(), newmark.energy.begin() + 500});
    std::printf(
        "%-12s 1000 steps of T1/40: Newmark max |E - E0|/E0 = %.2e (first 500 steps %.2e); implicit Euler "
        "keeps %.2e of E0\n",
        to_string(kind).c_str(), drift, first_half, euler.energy.back() / euler.energy.front());
    if (kind == MaterialKind::linear)
      EXPECT_LT(drift, 1e-8);
    else
      EXPECT_LT(drift, 2e-2);
    EXPECT_LT(euler.energy.back() / euler.energy.front(), 1e-3);
  }
}

TEST(Integrators, FreeVibrationPeriodMatchesModalAnalysis) {
  // Small-amplitude Neo-Hookean vibration: period from zero crossings of the first modal
  // coordinate vs 2 pi / omega_1 from K phi = lambda M phi, corrected by Newmark's period
  // elongation (omega~ h = 2 atan(omega h / 2)).
  Cantilever c;
  const CantileverModes modes = cantilever_modes(c, c.p, 1);
  const double omega = modes.omega[0], period = 2 * kPi / omega, h = period / 40;
  const Vector x0 = c.rest + 1e-4 * modes.shapes.col(0);
  const Trajectory run = simulate(c, c.p, TimeScheme::newmark, h, 160, x0, Vector::Zero(x0.size()));
  std::vector<double> crossings;
  double previous = modal_coordinate(modes, 0, run.states[0].x - c.rest);
  for (std::size_t n = 1; n < run.states.size(); ++n) {
    const double q = modal_coordinate(modes, 0, run.states[n].x - c.rest);
    if ((previous > 0) != (q > 0)) crossings.push_back(h * (n - 1 + previous / (previous - q)));
    previous = q;
  }
  ASSERT_GE(crossings.size(), 6u);
  const double measured = 2 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
  const double newmark_period = 2 * kPi * h / (2 * std::atan(omega * h / 2));
  std::printf(
      "first mode: omega %.4f, modal period %.5f, Newmark period %.5f, measured %.5f (%.2e relative)\n",
      omega, period, newmark_period, measured, measured / newmark_period - 1);
  EXPECT_NEAR(measured, newmark_period, 2e-3 * period);  // linear interpolation of crossings
  EXPECT_NEAR(measured, period, 0.01 * period);
}

TEST(Integrators, RayleighDampingRatioOfAMode) {
  // zeta_k = alpha / (2 omega_k) + beta omega_k / 2 (C = alpha M + beta K is diagonal in the
  // modal basis); measured by the logarithmic decrement between successive peaks,
  // delta = 2 pi zeta / sqrt(1 - zeta^2).
  struct Case {
    double alpha, beta;
    int mode;
  };
  for (const Case& k : {Case{0.3, 0.0, 0}, Case{0.0, 4e-3, 0}, Case{0.2, 1e-3, 1}}) {
    CantileverOptions o = linear_options();
    o.rayleigh = true, o.alpha = k.alpha, o.beta = k.beta;
    Cantilever c(o);
    const CantileverModes modes = cantilever_modes(c, c.p, 2);
    const double omega = modes.omega[k.mode], period = 2 * kPi / omega, h = period / 200;
    const double zeta = k.alpha / (2 * omega) + k.beta * omega / 2;
    const Vector x0 = c.rest + 0.01 * modes.shapes.col(k.mode);
    const Trajectory run = simulate(c, c.p, TimeScheme::newmark, h, 600, x0, Vector::Zero(x0.size()));
    std::vector<double> q;
    for (const auto& s : run.states) q.push_back(modal_coordinate(modes, k.mode, s.x - c.rest));
    std::vector<double> peaks;  // parabolic interpolation through three samples
    for (std::size_t n = 1; n + 1 < q.size(); ++n)
      if (q[n] > q[n - 1] && q[n] >= q[n + 1]) {
        const double a = 0.5 * (q[n - 1] - 2 * q[n] + q[n + 1]), b = 0.5 * (q[n + 1] - q[n - 1]);
        peaks.push_back(q[n] - b * b / (4 * a));
      }
    ASSERT_GE(peaks.size(), 2u);
    const double delta = std::log(peaks.front() / peaks.back()) / (peaks.size() - 1);
    const double measured = delta / std::sqrt(4 * kPi * kPi + delta * delta);
    std::printf("mode %d alpha %.2g beta %.2g: zeta expected %.5f, measured %.5f (%.2e relative)\n",
                k.mode + 1, k.alpha, k.beta, zeta, measured, measured / zeta - 1);
    EXPECT_NEAR(measured, zeta, 0.01 * zeta);
  }
}

TEST(Integrators, PrescribedMotionMovesTheClampedEnd) {
  Cantilever c;
  const std::vector<int> fixed = c.fixed_dofs;
  const Vector rest = c.rest;
  TimeIntegratorOptions o;
  o.scheme = TimeScheme::bdf2;
  o.time_step = 0.01;
  o.prescribed_motion = [rest, fixed](double t) {
    Vector offset = Vector::Zero(rest.size());
    for (int d : fixed) offset[d] = rest[d] + (d % 3 == 1 ? 0.1 * std::sin(10 * t) : 0.0);
    return offset;
  };
  TimeIntegrator integrator(*c.model, o);
  DynamicState s = integrator.initial_state(c.rest, Vector::Zero(c.rest.size()), c.p);
  for (int n = 0; n < 20; ++n) ASSERT_TRUE(integrator.step(s, c.p).converged());
  for (int d : fixed) EXPECT_NEAR(s.x[d], rest[d] + (d % 3 == 1 ? 0.1 * std::sin(10 * s.time) : 0.0), 1e-14);
  // The free end is set in motion by the base alone.
  EXPECT_GT(std::abs(s.x[3 * c.tip_vertices[0] + 1] - rest[3 * c.tip_vertices[0] + 1]), 1e-3);
}

TEST(Integrators, ReductionByProjectionReproducesAModalTrajectory) {
  // Linear elasticity with Rayleigh damping is diagonal in the modal basis: a motion started
  // in the span of modes 1 and 2 stays there, so the reduced model u = Phi q (Elimination::
  // general with a dense basis) gives the full trajectory, for every scheme.
  CantileverOptions o = linear_options();
  o.rayleigh = true, o.alpha = 0.1, o.beta = 1e-3;
  Cantilever full(o), reduced(o);
  const CantileverModes modes = cantilever_modes(full, full.p, 3);
  reduced.model->set_elimination(Elimination(full.rest, modes.shapes.sparseView()));
  const Vector x0 = full.rest + 0.01 * modes.shapes.col(0) - 0.005 * modes.shapes.col(1);
  const Vector v0 = 0.02 * modes.shapes.col(1);
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark, TimeScheme::bdf2}) {
    const Trajectory a = simulate(full, full.p, scheme, 0.02, 50, x0, v0);
    const Trajectory b = simulate(reduced, reduced.p, scheme, 0.02, 50, x0, v0);
    EXPECT_EQ(b.states.back().y.size(), 3);
    const double scale = (a.states.back().x - full.rest).norm();
    EXPECT_LT((a.states.back().x - b.states.back().x).norm(), 1e-8 * scale) << to_string(scheme);
    EXPECT_LT((a.states.back().v - b.states.back().v).norm(), 1e-7 * a.states.back().v.norm())
        << to_string(scheme);
  }
}

TEST(Integrators, NewmarkRestartKeepsTheConstantFactorization) {
  // A linear damped cantilever has a constant step Hessian. Newmark's start evaluates g_0 with
  // the inertia and damping coefficients of the start (c = 0, kappa = h), then its steps use
  // c = 4/h^2, kappa = h/2: a second run from the initial state (an optimizer's next forward
  // pass at the same design, or the adjoint after it) returns to the same Hessian and keeps its
  // factorization, while a different time step must factorize.
  CantileverOptions o = linear_options();
  o.rayleigh = true, o.alpha = 0.1, o.beta = 1e-3;
  o.gravity = Eigen::Vector3d(0.0, 0.0, -1.0);
  Cantilever c(o);
  TimeIntegratorOptions options;
  options.scheme = TimeScheme::newmark;
  options.time_step = 0.02;
  TimeIntegrator integrator(*c.model, options);
  auto run = [&](int steps) {
    DynamicState s = integrator.initial_state(c.rest, Vector::Zero(c.rest.size()), c.p);
    int factorizations = 0;
    for (int n = 0; n < steps; ++n) {
      const NewtonResult r = integrator.step(s, c.p);
      EXPECT_TRUE(r.converged()) << r.message;
      factorizations += r.factorizations();
    }
    return std::make_pair(factorizations, s.x);
  };
  const auto [first, x_first] = run(5);
  const auto [second, x_second] = run(5);
  EXPECT_EQ(first, 1);
  EXPECT_EQ(second, 0);
  EXPECT_EQ((x_first - x_second).norm(), 0.0);
  TimeIntegratorOptions other = options;
  other.time_step = 0.01;
  TimeIntegrator finer(*c.model, other);
  DynamicState s = finer.initial_state(c.rest, Vector::Zero(c.rest.size()), c.p);
  EXPECT_EQ(finer.step(s, c.p).factorizations(), 1);
}

}  // namespace
}  // namespace tailor::integrator_validation_test
