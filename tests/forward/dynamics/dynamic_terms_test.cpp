// Derivative checks of the dynamic energy terms (inertia, Rayleigh damping, gravity with
// density, time-varying loads), the mass operator against mass_matrix(), the rest stiffness
// that Rayleigh damping uses, and a corrupted derivative that the check must reject.
#include <gtest/gtest.h>

#include <cstdio>

#include "../../support/dynamics_fixtures.hpp"
#include "adjoint/derivative_check.hpp"
#include "forward/fem/loads.hpp"

namespace tailor::dynamic_terms_test {
namespace {

using namespace tailor::testing;

Vector random_vector(Eigen::Index n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = scale * u(rng);
  return v;
}

// Heterogeneous parameters so that every per-element derivative is exercised.
Vector varied(const Cantilever& c, unsigned seed) {
  Vector p = c.p;
  const Vector r = random_vector(p.size(), seed, 0.3);
  for (Eigen::Index i = 0; i < p.size(); ++i) p[i] *= 1.0 + r[i];
  return p;
}

void expect_passes(const EnergyTerm& term, const Vector& x, const Vector& p) {
  const EnergyTermCheck check = check_energy_term(term, x, p);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
}

TEST(DynamicTerms, InertiaDerivativesConsistentAndLumped) {
  for (MassLumping lumping : {MassLumping::consistent, MassLumping::lumped}) {
    CantileverOptions o;
    o.lumping = lumping;
    Cantilever c(o);
    const Vector p = varied(c, 5);
    const Vector x = c.rest + random_vector(c.rest.size(), 7, 0.2);
    c.terms.inertia->set_step(37.0, c.rest + random_vector(c.rest.size(), 9, 0.2),
                              random_vector(c.rest.size(), 11, 1.0));
    expect_passes(*c.terms.inertia, x, p);
    // Its Hessian product (c M w by the mass operator) against the Hessian on the pattern.
    const Vector w = random_vector(c.rest.size(), 13, 1.0);
    Vector fast = Vector::Zero(x.size()), reference = Vector::Zero(x.size());
    c.terms.inertia->add_hessian_times(x, p, w, fast);
    c.terms.inertia->EnergyTerm::add_hessian_times(x, p, w, reference);
    EXPECT_LT((fast - reference).norm(), 1e-12 * reference.norm());
  }
}

TEST(DynamicTerms, MassOperatorMatchesMassMatrix) {
  for (MassLumping lumping : {MassLumping::consistent, MassLumping::lumped}) {
    CantileverOptions o;
    o.lumping = lumping;
    Cantilever c(o);
    const Vector p = varied(c, 13);
    const Eigen::VectorXd density = p.segment(c.terms.density_offset, c.num_elements());
    const SparseMatrix reference = mass_matrix(c.mesh, density, lumping);
    EXPECT_LT((Matrix(c.terms.inertia->mass().matrix(p)) - Matrix(reference)).norm(),
              1e-12 * Matrix(reference).norm());
  }
}

TEST(DynamicTerms, RayleighDampingDerivatives) {
  CantileverOptions o;
  o.rayleigh = true, o.alpha = 0.7, o.beta = 0.03;
  Cantilever c(o);
  const Vector p = varied(c, 17);
  const Vector x = c.rest + random_vector(c.rest.size(), 19, 0.2);
  c.terms.damping->set_velocity_map(0.01, c.rest + random_vector(c.rest.size(), 23, 0.2));
  expect_passes(*c.terms.damping, x, p);
  // The default mixed block (through the transpose product) agrees with the explicit one.
  Triplets explicit_mixed, generic_mixed;
  c.terms.damping->add_dissipation_mixed(c.terms.damping->velocity(x), p, explicit_mixed);
  c.terms.damping->DampingTerm::add_dissipation_mixed(c.terms.damping->velocity(x), p, generic_mixed);
  SparseMatrix a(x.size(), p.size()), b(x.size(), p.size());
  a.setFromTriplets(explicit_mixed.begin(), explicit_mixed.end());
  b.setFromTriplets(generic_mixed.begin(), generic_mixed.end());
  EXPECT_LT((Matrix(a) - Matrix(b)).norm(), 1e-10 * Matrix(a).norm());
}

TEST(DynamicTerms, RayleighDampingFollowsChangedModuli) {
  // The damping keeps K assembled for the moduli it last saw; D and its gradient must follow
  // new moduli (and return to the old ones). Reference: D = alpha/2 v^T M v + beta E_lin(X + v)
  // with the small-strain energy E_lin evaluated element by element for the same moduli.
  CantileverOptions o;
  o.rayleigh = true, o.alpha = 0.7, o.beta = 0.03;
  Cantilever c(o);
  const Vector v = random_vector(c.rest.size(), 31, 0.1);
  const auto linear = elastic_term<3>(c.mesh, MaterialKind::linear);
  for (unsigned seed : {41u, 43u, 41u}) {
    const Vector p = varied(c, seed);
    double D = 0.0;
    Vector g = Vector::Zero(v.size());
    EnergyRequest request;
    request.value = &D;
    request.gradient = &g;
    c.terms.damping->evaluate_dissipation(v, p, request);
    const double alpha = p[c.terms.alpha_offset], beta = p[c.terms.beta_offset];
    const SparseMatrix M = c.terms.inertia->mass().matrix(p);
    Vector Kv = Vector::Zero(v.size());
    linear->add_gradient(c.rest + v, p, Kv);
    const double reference = 0.5 * alpha * v.dot(M * v) + beta * linear->value(c.rest + v, p);
    const Vector g_reference = alpha * (M * v) + beta * Kv;
    EXPECT_NEAR(D, reference, 1e-12 * std::abs(reference)) << seed;
    EXPECT_LT((g - g_reference).norm(), 1e-12 * g_reference.norm()) << seed;
  }
}

TEST(DynamicTerms, RayleighHessianTimesFollowsItsHessianAndChangedModuli) {
  // The adjoint's product (alpha M + beta K) w / kappa with the kept K against the Hessian
  // values on the pattern (EnergyTerm's default), for three parameter vectors in turn: a K kept
  // from the previous moduli would miss by the change of the moduli (30%).
  CantileverOptions o;
  o.rayleigh = true, o.alpha = 0.7, o.beta = 0.03;
  Cantilever c(o);
  const Vector x = c.rest + random_vector(c.rest.size(), 53, 0.2);
  const Vector w = random_vector(c.rest.size(), 59, 1.0);
  c.terms.damping->set_velocity_map(0.01, c.rest + random_vector(c.rest.size(), 61, 0.2));
  for (unsigned seed : {41u, 43u, 41u}) {
    const Vector p = varied(c, seed);
    Vector fast = Vector::Zero(x.size()), reference = Vector::Zero(x.size());
    c.terms.damping->add_hessian_times(x, p, w, fast);
    c.terms.damping->EnergyTerm::add_hessian_times(x, p, w, reference);
    EXPECT_LT((fast - reference).norm(), 1e-12 * reference.norm()) << seed;
  }
}

TEST(DynamicTerms, RayleighStiffnessIsTheRestTangentOfEveryMaterial) {
  // K in C = alpha M + beta K is the Hessian of the small-strain energy; at rest every
  // material with the same Lame parameters has that Hessian (linearization of hyperelasticity).
  for (MaterialKind kind : {MaterialKind::neo_hookean, MaterialKind::stvk, MaterialKind::corotated}) {
    CantileverOptions o;
    o.material = kind, o.rayleigh = true;
    Cantilever c(o);
    const Vector p = varied(c, 29);
    const Matrix K = Matrix(c.terms.damping->rest_stiffness(p));
    const Matrix H = Matrix(c.model->terms()[0]->hessian(c.rest, p, HessianMode::exact));
    EXPECT_LT((K - H).norm(), 1e-9 * K.norm()) << to_string(kind);
  }
}

TEST(DynamicTerms, GravityWithDensityDerivatives) {
  CantileverOptions o;
  o.gravity = Eigen::Vector3d(0.0, -1.0, -9.81);
  Cantilever c(o);
  const Vector p = varied(c, 31);
  const Vector x = c.rest + random_vector(c.rest.size(), 37, 0.2);
  // Linear in x: the Hessian check reports "vanishing", every other check must pass.
  const EnergyTermCheck check = check_energy_term(*c.terms.gravity, x, p);
  for (const DerivativeCheck& d : check.checks) {
    if (d.quantity == "hessian")
      EXPECT_TRUE(d.vanishing) << check.table();
    else
      EXPECT_TRUE(d.passed) << d.quantity << "\n" << check.table();
  }
  // Same forces as gravity_forces() for the same densities.
  Vector g = Vector::Zero(x.size());
  c.terms.gravity->add_gradient(x, p, g);
  const Vector f = gravity_forces(c.mesh, p.segment(c.terms.density_offset, c.num_elements()),
                                  Eigen::Vector3d(0.0, -1.0, -9.81));
  EXPECT_LT((g + f).norm(), 1e-12 * f.norm());
}

TEST(DynamicTerms, TimeVaryingLoadFollowsItsMagnitude) {
  const Mesh mesh = small_mesh(3);
  const Vector f = random_vector(3 * mesh.num_vertices(), 41, 1.0);
  TimeVaryingLoadTerm load(f, [](double t) { return std::sin(t); });
  load.set_time(0.5);
  const Vector x = rest_state(mesh) + random_vector(f.size(), 43, 0.1);
  EXPECT_NEAR(load.value(x, Vector()), -std::sin(0.5) * f.dot(x), 1e-12);
  const EnergyTermCheck check = check_energy_term(load, x, Vector());
  EXPECT_TRUE(check.checks.front().passed) << check.table();
  EXPECT_THROW(TimeVaryingLoadTerm(f, [](double) { return std::nan(""); }), std::invalid_argument);
}

// Inertia whose Hessian is off by a relative 1e-4: the check must fail.
class CorruptedInertia final : public EnergyTerm {
 public:
  explicit CorruptedInertia(const InertiaTerm& inner) : inner_(inner) {}
  std::string name() const override { return "corrupted_inertia"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    inner_.evaluate(x, p, request);
    if (request.hessian_values) {
      HessianPattern pattern;
      hessian_pattern(pattern);
      for (std::size_t k = 0; k < pattern.size(); ++k) request.hessian_values[k] *= 1.0 + 1e-4;
    }
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& g) const override {
    inner_.add_param_gradient(x, p, g);
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& m) const override { inner_.add_mixed(x, p, m); }

 private:
  const InertiaTerm& inner_;
};

TEST(DynamicTerms, CorruptedInertiaHessianIsRejected) {
  Cantilever c;
  const Vector p = varied(c, 47);
  const Vector x = c.rest + random_vector(c.rest.size(), 53, 0.2);
  c.terms.inertia->set_step(50.0, c.rest);
  const EnergyTermCheck check = check_energy_term(CorruptedInertia(*c.terms.inertia), x, p);
  bool hessian_failed = false;
  for (const DerivativeCheck& d : check.checks)
    if (d.quantity == "hessian") hessian_failed = !d.passed && !d.vanishing && d.best_error > 1e-5;
  EXPECT_TRUE(hessian_failed) << check.table();
  EXPECT_FALSE(check.passed());
}

TEST(DynamicTerms, BadInputIsRejected) {
  Cantilever c;
  EXPECT_THROW(c.terms.inertia->set_step(-1.0, c.rest), std::invalid_argument);
  EXPECT_THROW(c.terms.inertia->set_step(1.0, Vector::Zero(3)), std::invalid_argument);
  TimeIntegratorOptions o;
  o.time_step = 0.0;
  EXPECT_THROW(TimeIntegrator(*c.model, o), std::invalid_argument);
  Model empty(3);
  EXPECT_THROW(TimeIntegrator(empty, TimeIntegratorOptions{}), std::invalid_argument);
  EXPECT_THROW(parse_time_scheme("leapfrog"), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::dynamic_terms_test
