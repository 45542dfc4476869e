// Rods in dynamics: lumped vertex masses and twist inertias rho (I1 + I2) L in the existing time
// integrators (forward/dynamics/time_integrator.hpp), reference frames moved to each new state.
// References:
//  - bending: a clamped-free rod released from its first Euler-Bernoulli mode shape oscillates at
//    omega_1 = (beta_1 L)^2 sqrt(EI / (rho A L^4)), beta_1 L = 1.8751040687 (cos bL cosh bL = -1;
//    Timoshenko, "Vibration Problems in Engineering");
//  - torsion: released from its first torsional mode, at omega_t = (pi / 2L) sqrt(GJ / (rho I_p))
//    (the wave equation rho I_p theta_tt = GJ theta_ss, clamped-free), I_p = J for a circle;
//  - energy: the trapezoidal rule (newmark) conserves 1/2 v^T M v + E for linear problems, so at
//    this small amplitude the total energy stays constant; implicit Euler multiplies a linear
//    oscillator's energy by 1 / (1 + (omega h)^2) per step (its amplification factor
//    1 / (1 + i omega h) squared in modulus).
// The grid is the staggered one of tests/forward/rods (clamped edge centred on s = 0, the last
// edge's midpoint at s = L); the vertex past the end carries no mass and the last edge half its
// twist inertia, so that the masses are those of the Voronoi cells tiling [0, L].
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/scene_kinds.hpp"
#include "rod_scene_files.hpp"

namespace tailor::rod_dynamics_test {
namespace {

using testing::read_json_file;
using testing::read_rod_scene;
using testing::rod_scene_path;

constexpr double kBeta1 = 1.8751040687;

RodSceneSpec staggered_cantilever(int n) {
  const double r = 1e-2, L = 1.0, h = L / n;
  RodSpec rod;
  rod.name = "beam";
  rod.points = Eigen::MatrixX3d::Zero(n + 2, 3);
  for (int i = 0; i < n + 2; ++i) rod.points(i, 0) = (i - 0.5) * h;
  rod.material.radius = r;
  rod.material.youngs_modulus = 4.0 / (M_PI * std::pow(r, 4));  // EI = 1
  rod.material.shear_modulus = rod.material.youngs_modulus / 2.6;
  rod.density = 1.0 / (M_PI * r * r);  // rho A = 1
  rod.clamped = {RodEnd::first};
  RodSceneSpec spec;
  spec.rods.push_back(rod);
  return spec;
}

// The first Euler-Bernoulli cantilever mode at s (L = 1), normalized to 1 at the tip.
double bending_mode(double s) {
  const double b = kBeta1, sigma = (std::cosh(b) + std::cos(b)) / (std::sinh(b) + std::sin(b));
  auto phi = [&](double t) {
    return std::cosh(b * t) - std::cos(b * t) - sigma * (std::sinh(b * t) - std::sin(b * t));
  };
  return phi(s) / phi(1.0);
}

// Period of a signal from its zero crossings (linear interpolation between samples).
double period_from_crossings(const std::vector<double>& t, const std::vector<double>& y) {
  std::vector<double> crossings;
  for (std::size_t k = 1; k < y.size(); ++k)
    if ((y[k - 1] < 0.0) != (y[k] < 0.0))
      crossings.push_back(t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]));
  EXPECT_GE(crossings.size(), 4u);
  if (crossings.size() < 2) return 0.0;
  return 2.0 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

struct Released {
  double omega = 0.0;         // measured from the zero crossings
  double energy_drift = 0.0;  // max |E(t) - E(0)| / E(0)
  double energy_ratio = 0.0;  // E(end) / E(0)
  int steps = 0;
};

// Releases the n-cell cantilever from its first bending (torsion = false) or torsional mode of
// small amplitude and integrates `periods` periods of the reference frequency omega_ref with
// `steps_per_period` steps.
Released release(int n, bool torsion, TimeScheme scheme, double omega_ref, int steps_per_period,
                 int periods) {
  const RodSceneSpec spec = staggered_cantilever(n);
  RodSceneModel m = build_rod_model(spec);
  const DiscreteRod& rod = *m.rods[0];
  Vector mass = rod_scene_mass_diagonal(spec, m);
  mass.segment<3>(rod.position_dof(n + 1, 0)).setZero();  // past the end: no mass
  mass[rod.twist_dof(n)] *= 0.5;                          // last edge: half cell
  add_rod_inertia(m, mass);
  const double h = 1.0 / n;
  Vector x0 = m.rest;
  for (int v = 2; v < n + 2; ++v) {
    const double s = (v - 0.5) * h;
    if (!torsion) x0[rod.position_dof(v, 1)] = 1e-4 * bending_mode(s);
  }
  if (torsion)
    for (int j = 1; j <= n; ++j) x0[rod.twist_dof(j)] = 1e-3 * std::sin(0.5 * M_PI * j * h);
  DynamicsSpec d;
  d.scheme = scheme;
  d.time_step = 2.0 * M_PI / omega_ref / steps_per_period;
  d.steps = steps_per_period * periods;
  std::vector<double> t, y;
  const RodDynamicsRun run =
      integrate_rods(m, d, x0, Vector::Zero(x0.size()), "", nullptr, [&](const DynamicState& s) {
        t.push_back(s.time);
        // At the rod's end s = L: the last edge's midpoint, or its twist.
        y.push_back(torsion ? s.x[rod.twist_dof(n)]
                            : 0.5 * (s.x[rod.position_dof(n, 1)] + s.x[rod.position_dof(n + 1, 1)]));
      });
  EXPECT_TRUE(run.completed) << run.message;
  Released r;
  r.omega = 2.0 * M_PI / period_from_crossings(t, y);
  const double e0 = run.kinetic_energy.front() + run.potential_energy.front();
  for (std::size_t k = 0; k < run.time.size(); ++k)
    r.energy_drift =
        std::max(r.energy_drift, std::abs(run.kinetic_energy[k] + run.potential_energy[k] - e0) / e0);
  r.energy_ratio = (run.kinetic_energy.back() + run.potential_energy.back()) / e0;
  r.steps = run.steps;
  return r;
}

TEST(RodDynamics, ReleasedCantileverOscillatesAtFirstEulerBernoulliFrequency) {
  const double omega = kBeta1 * kBeta1;  // EI = rho A = L = 1
  const Released coarse = release(10, false, TimeScheme::newmark, omega, 100, 3);
  const Released fine = release(20, false, TimeScheme::newmark, omega, 100, 3);
  const double e10 = std::abs(coarse.omega / omega - 1.0), e20 = std::abs(fine.omega / omega - 1.0);
  std::printf(
      "released cantilever (newmark, T/100): omega_1 errors %.3e (n = 10), %.3e (n = 20); "
      "energy drift %.2e\n",
      e10, e20, fine.energy_drift);
  // Spatial error 5.3e-3 / 1.3e-3 (RodVibration) plus the trapezoidal rule's (omega h)^2 / 12 = 3.3e-4.
  EXPECT_LT(e20, 2e-3);
  EXPECT_GT(e10 / e20, 3.0);
  EXPECT_LT(fine.energy_drift, 1e-4);
}

TEST(RodDynamics, TwistInertiaGivesTheTorsionalFrequency) {
  const RodSceneSpec spec = staggered_cantilever(20);  // kept: r refers into it
  const RodSpec& r = spec.rods[0];
  const double omega =
      0.5 * M_PI * std::sqrt(r.material.shear_modulus / r.density);  // GJ / (rho I_p) = G / rho
  const Released run = release(20, true, TimeScheme::newmark, omega, 100, 2);
  const double error = std::abs(run.omega / omega - 1.0);
  std::printf("torsion (n = 20, newmark, T/100): omega_t error %.3e, energy drift %.2e\n", error,
              run.energy_drift);
  EXPECT_LT(error, 1e-3);  // a twist inertia off by a factor 2 would give 29%
  EXPECT_LT(run.energy_drift, 1e-4);
}

TEST(RodDynamics, ImplicitEulerLosesEnergyAsDocumented) {
  const double omega = kBeta1 * kBeta1;
  const int per_period = 50;
  const Released run = release(20, false, TimeScheme::implicit_euler, omega, per_period, 2);
  const double wh = omega * 2.0 * M_PI / omega / per_period;  // omega h for the EB frequency
  const double predicted = std::pow(1.0 + wh * wh, -run.steps);
  std::printf("implicit Euler (T/50, 2 periods): E_end / E_0 = %.4f, linear prediction %.4f\n",
              run.energy_ratio, predicted);
  EXPECT_NEAR(run.energy_ratio / predicted, 1.0, 2e-2);
}

// The shipped dynamic scene through `tailor simulate`'s entry point: frames, .pvd and report.
TEST(RodDynamics, ShippedSwingingRodSceneWritesFramesAndReport) {
  const auto dir = testing::unique_temp_path("tailor_rod_dynamics_scene");
  std::filesystem::remove_all(dir);
  std::ostringstream log;
  const SceneFile file = read_scene_file(rod_scene_path("rod_swing.json"));
  ASSERT_TRUE(simulate_rod_scene(file.node(), file.directory(), dir.string(), &log)) << log.str();
  testing::expect_report_header((dir / "report.json").string());
  const nlohmann::json report = read_json_file((dir / "report.json").string());
  EXPECT_EQ(report["status"], "completed");
  EXPECT_TRUE(report.contains("threads"));
  const int steps = report["steps"];
  EXPECT_EQ(steps, report["steps_requested"].get<int>());
  for (const auto& frame : report["frames"])
    EXPECT_TRUE(std::filesystem::exists(dir / frame.get<std::string>()));
  EXPECT_TRUE(std::filesystem::exists(dir / "rods.pvd"));
  // Newmark on a large swing (nonlinear): the energy is not conserved exactly but stays bounded.
  const double e0 = report["energy_initial"], e1 = report["energy_final"];
  double largest_kinetic = 0.0;
  for (double k : report["series"]["kinetic_energy"]) largest_kinetic = std::max(largest_kinetic, k);
  std::printf("swinging rod: %d steps, |E_end - E_0| / max kinetic = %.2e\n", steps,
              std::abs(e1 - e0) / largest_kinetic);
  EXPECT_GT(largest_kinetic, 0.0);
  EXPECT_LT(std::abs(e1 - e0), 0.05 * largest_kinetic);
  std::filesystem::remove_all(dir);
}

TEST(RodDynamics, BadDynamicsKeysNameTheKey) {
  const nlohmann::json scene = read_rod_scene("rod_swing.json");
  auto expect_error = [](const nlohmann::json& s, const std::string& key) {
    try {
      parse_rod_scene(s);
      ADD_FAILURE() << "expected an error naming " << key;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  nlohmann::json s = scene;
  s["dynamics"]["rayleigh"] = {{"alpha", 1.0}};
  expect_error(s, "dynamics.rayleigh");
  s = scene;
  s["dynamics"]["mass"] = "consistent";
  expect_error(s, "dynamics.mass");
  s = scene;
  s["rods"][0]["material"].erase("density");
  expect_error(s, "rods[0].material.density");
  s = scene;
  s["dynamics"].erase("time_step");
  expect_error(s, "dynamics");
  s = scene;
  s["dynamics"]["initial_velocity"] = {1.0, 2.0};
  expect_error(s, "dynamics.initial_velocity");
}

}  // namespace
}  // namespace tailor::rod_dynamics_test
