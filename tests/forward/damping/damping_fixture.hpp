#pragma once
// A clamped bar of tets with example-based damping on top of Rayleigh damping, for tests:
// p = [youngs_modulus (m), poisson_ratio (m), density (m), alpha, beta, curve controls].
#include <memory>

#include "../../support/dynamics_fixtures.hpp"
#include "forward/dynamics/example_damping_setup.hpp"

namespace tailor::testing {

inline Vector random_vector(Eigen::Index n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = scale * u(rng);
  return v;
}

struct DampedBar {
  Cantilever bar;
  ExampleDampingTerms damping;
  Vector p;

  // Examples: bending in z and in y (x^2 profiles) and, optionally, a twist-like random field
  // that is not a mode, so that the coupling terms are exercised.
  DampedBar(
      std::vector<DampingCurve> curves, bool random_third = false,
      const CantileverOptions& o =
          [] {
            CantileverOptions c;
            c.material = MaterialKind::linear;
            c.cells = 4;
            return c;
          }())
      : bar(o) {
    ExampleDampingSetup setup;
    const int n = bar.model->num_dofs();
    Vector bend_z = Vector::Zero(n), bend_y = Vector::Zero(n);
    for (int v = 0; v < bar.mesh.num_vertices(); ++v) {
      const double x = bar.mesh.rest_positions(v, 0) / o.length;
      bend_z[3 * v + 2] = x * x;
      bend_y[3 * v + 1] = x * x;
    }
    DampingExampleSpec a, b;
    a.source = b.source = DampingExampleSpec::Source::displacement;
    a.field = bend_z, b.field = bend_y;
    setup.examples = {a, b};
    if (random_third) {
      DampingExampleSpec c;
      c.source = DampingExampleSpec::Source::displacement;
      c.field = bar.model->elimination().expand_direction(
          random_vector(bar.model->elimination().num_free(), 17, 0.1));
      setup.examples.push_back(c);
    }
    for (std::size_t i = 0; i < setup.examples.size(); ++i) setup.examples[i].curve = curves.at(i);
    damping = add_example_damping(*bar.model, bar.mesh, bar.terms.inertia->mass_ptr(), bar.p, setup);
    p = Vector::Zero(bar.model->parameter_layout().size());
    p.head(bar.p.size()) = bar.p;
    p[damping.alpha_offset] = 0.3;
    p[damping.beta_offset] = 0.01;
  }
  ExampleDamping& term() { return *damping.damping; }
  void set_scale(int i, double gamma) { p[damping.curve_offset + term().curve_begin(i)] = gamma; }
  void set_controls(int i, const Vector& values) {
    p.segment(damping.curve_offset + term().curve_begin(i), values.size()) = values;
  }
};

inline std::vector<DampingCurve> constant_curves(int count) {
  return std::vector<DampingCurve>(static_cast<std::size_t>(count));
}

}  // namespace tailor::testing
