// The handle objective of heterogeneous material design (Xu, Li, Chen, Barbic 2015):
//  - its value at equilibrium equals the paper's Schur-complement formula
//    alpha/2 |K~ u~ + K21 K11^-1 fhat - fbar|_W^2 + alpha beta/2 |u~ - ubar|^2,
//    K~ = K22 - K21 K11^-1 K12, computed here with dense matrices (the reference);
//  - its partial derivatives match differences, and restricting the reaction terms to the
//    elements that touch the handles changes nothing;
//  - the reduced functional z = [log E, u~] -> J passes Taylor tests (linear, Neo-Hookean).
#include "objectives/handle_objective.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/loads.hpp"
#include "objective_checks.hpp"

namespace tailor::handle_objective_test {
namespace {

using testing::random_vector;

// A 3 x 1 x 1 bar of tets clamped at X = 0, free vertices loaded by random forces fhat.
// Handle 0: the tip face X = 3 (total force and displacement targets); handle 1: one top
// vertex in the middle (per-vertex force target, no displacement target).
struct HandleBar {
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 1, 1), 3, 1, 1);
  std::unique_ptr<Model> model;
  std::vector<std::shared_ptr<const EnergyTerm>> terms;  // shared with the objective
  std::vector<int> clamped_dofs;
  Vector rest, loads, base;
  std::shared_ptr<HandleObjective> objective;
  int m = 0, handle_offset = 0;

  explicit HandleBar(MaterialKind kind, HandleObjectiveOptions options = {0.7, 2.5}) {
    m = mesh.num_elements();
    const int n = 3 * mesh.num_vertices();
    model = std::make_unique<Model>(n);
    model->parameter_layout().add("youngs_modulus", m);
    model->parameter_layout().add("poisson_ratio", m);
    rest = testing::rest_state(mesh);

    std::vector<Handle> handles(2);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const Eigen::RowVector3d X = mesh.rest_positions.row(v);
      if (X[0] < 1e-9)
        for (int k = 0; k < 3; ++k) clamped_dofs.push_back(3 * v + k);
      if (X[0] > 3 - 1e-9) handles[0].vertices.push_back(v);
    }
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (std::abs(mesh.rest_positions(v, 0) - 2) < 1e-9 && mesh.rest_positions(v, 2) > 1 - 1e-9) {
        handles[1].vertices.push_back(v);
        break;
      }
    handles[0].target_displacement = Eigen::RowVector3d(0.0, 0.02, -0.1);
    handles[0].target_force = Eigen::Vector3d(0.1, 0.3, -2.0);
    handles[0].weight = 1.5;
    handles[1].target_force = Eigen::Vector3d(0.0, -0.4, 0.5);
    handles[1].weight = 0.5;

    // fhat on the free vertices only (the paper's block 1).
    loads = Vector::Zero(n);
    const Vector random = random_vector(n, 31, 0.2);
    std::vector<bool> constrained(static_cast<std::size_t>(n), false);
    for (int d : clamped_dofs) constrained[static_cast<std::size_t>(d)] = true;
    for (const Handle& h : handles)
      for (int v : h.vertices)
        for (int k = 0; k < 3; ++k) constrained[static_cast<std::size_t>(3 * v + k)] = true;
    for (int d = 0; d < n; ++d)
      if (!constrained[static_cast<std::size_t>(d)]) loads[d] = random[d];

    terms.push_back(std::shared_ptr<const EnergyTerm>(testing::elastic_term<3>(mesh, kind)));
    terms.push_back(std::make_shared<ExternalForceTerm>(loads));
    // The model owns its own copies of the same terms.
    model->add(testing::elastic_term<3>(mesh, kind));
    model->add(std::make_unique<ExternalForceTerm>(loads));

    std::vector<int> fixed = clamped_dofs;
    handle_offset = model->parameter_layout().size();
    objective = std::make_shared<HandleObjective>(terms, n, 3, handles, handle_offset, options);
    fixed.insert(fixed.end(), objective->dofs().begin(), objective->dofs().end());
    model->set_elimination(Elimination::dirichlet(fixed, rest));
    EXPECT_EQ(model->add_prescribed_displacements("handle_displacement", objective->dofs()), handle_offset);

    base = testing::heterogeneous_parameters(mesh, 100.0, 0.3);
    base.conservativeResize(model->parameter_layout().size());
    base.tail(objective->displacement_size()).setZero();
  }

  ParameterizationPtr design_map() const {
    return embed_blocks(base,
                        {{0, exp_map(m)}, {handle_offset, identity_map(objective->displacement_size())}});
  }
  std::unique_ptr<StaticFunctional> functional() const {
    return std::make_unique<StaticFunctional>(*model, design_map(), objective,
                                              model->elimination().restrict_state(rest));
  }
  // z = [log E (random around 100), u~ (random, the tip pulled down)].
  Vector design(unsigned seed) const {
    Vector z(m + objective->displacement_size());
    z.head(m) = base.head(m).array().log().matrix();
    z.tail(objective->displacement_size()) = random_vector(objective->displacement_size(), seed, 0.03);
    return z;
  }
};

TEST(HandleObjective, EqualsSchurComplementFormulaForLinearElasticity) {
  const HandleObjectiveOptions options{0.7, 2.5};
  HandleBar bar(MaterialKind::linear, options);
  auto f = bar.functional();
  const Vector z = bar.design(41);
  const double J = f->value(z);
  const Vector p = bar.design_map()->apply(z);

  // Dense stiffness K (exact for the linear material) and the block split.
  const Matrix K = Matrix(bar.terms[0]->hessian(bar.rest, p, HessianMode::exact));
  const std::vector<int>& block2 = bar.objective->dofs();
  std::vector<bool> constrained(static_cast<std::size_t>(K.rows()), false);
  for (int d : bar.clamped_dofs) constrained[static_cast<std::size_t>(d)] = true;
  for (int d : block2) constrained[static_cast<std::size_t>(d)] = true;
  std::vector<int> block1;
  for (int d = 0; d < K.rows(); ++d)
    if (!constrained[static_cast<std::size_t>(d)]) block1.push_back(d);
  const auto n1 = static_cast<Eigen::Index>(block1.size()), n2 = static_cast<Eigen::Index>(block2.size());
  Matrix K11(n1, n1), K12(n1, n2), K21(n2, n1), K22(n2, n2);
  for (Eigen::Index i = 0; i < n1; ++i) {
    for (Eigen::Index j = 0; j < n1; ++j) K11(i, j) = K(block1[i], block1[j]);
    for (Eigen::Index j = 0; j < n2; ++j) K12(i, j) = K(block1[i], block2[j]);
  }
  for (Eigen::Index i = 0; i < n2; ++i) {
    for (Eigen::Index j = 0; j < n1; ++j) K21(i, j) = K(block2[i], block1[j]);
    for (Eigen::Index j = 0; j < n2; ++j) K22(i, j) = K(block2[i], block2[j]);
  }
  Vector fhat(n1);
  for (Eigen::Index i = 0; i < n1; ++i) fhat[i] = bar.loads[block1[i]];
  const Eigen::LDLT<Matrix> K11_factor(K11);
  const Matrix schur = K22 - K21 * K11_factor.solve(K12);
  const Vector u_tilde = z.tail(n2);
  const Vector force = schur * u_tilde + K21 * K11_factor.solve(fhat);  // per handle DOF

  double reference = 0.0;
  int offset = 0;
  for (int h = 0; h < bar.objective->num_handles(); ++h) {
    const Handle& handle = bar.objective->handle(h);
    const int size = 3 * static_cast<int>(handle.vertices.size());
    Vector total = Vector::Zero(3);
    for (int i = 0; i < size; ++i) total[i % 3] += force[offset + i];
    if (handle.target_force.size() > 0)
      reference += 0.5 * options.alpha * handle.weight * (total - handle.target_force).squaredNorm();
    if (handle.target_displacement.size() > 0)
      for (int i = 0; i < size; ++i)
        reference += 0.5 * options.alpha * options.beta *
                     std::pow(u_tilde[offset + i] - handle.target_displacement(0, i % 3), 2);
    // The objective's own diagnostics agree with the formula too.
    EXPECT_LE((bar.objective->total_force(h, f->state(), p) - total).norm(), 1e-9 * total.norm());
    offset += size;
  }
  std::printf("J = %.15g, Schur-complement formula = %.15g\n", J, reference);
  EXPECT_NEAR(J, reference, 1e-9 * reference);
  EXPECT_NEAR(bar.objective->force_term(f->state(), p) + bar.objective->displacement_term(f->state(), p), J,
              1e-14 * J);
}

TEST(HandleObjective, DerivativesMatchDifferences) {
  HandleBar bar(MaterialKind::neo_hookean);
  const Vector p = bar.design_map()->apply(bar.design(43));
  const Vector x = bar.rest + random_vector(bar.rest.size(), 47, 0.02);
  const HandleObjective& J = *bar.objective;
  const Vector dx = random_vector(x.size(), 53);
  const Vector dp =
      testing::relative_direction(p, 59) +
      bar.design_map()->jacobian_times(bar.design(43), random_vector(bar.design(43).size(), 61, 0.01));
  const Vector no_dx = Vector::Zero(x.size()), no_dp = Vector::Zero(p.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, x, p, dx));
  TAILOR_EXPECT_CHECK(testing::check_gradient_p(J, x, p, dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, x, p, dx, no_dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, x, p, no_dx, dp));
  testing::expect_least_squares_consistent(J, x, p);
  EXPECT_FALSE(J.has_second_derivatives());
}

// Only the elements touching a handle contribute to its reaction: terms restricted to them
// give the same value and gradients.
TEST(HandleObjective, RestrictedReactionTermsGiveTheSameObjective) {
  HandleBar bar(MaterialKind::neo_hookean);
  std::vector<bool> on_handle(static_cast<std::size_t>(bar.mesh.num_vertices()), false);
  for (int d : bar.objective->dofs()) on_handle[static_cast<std::size_t>(d / 3)] = true;
  std::vector<int> touching;
  for (int e = 0; e < bar.m; ++e)
    for (int a = 0; a < 4; ++a)
      if (on_handle[static_cast<std::size_t>(bar.mesh.elements(e, a))]) {
        touching.push_back(e);
        break;
      }
  ASSERT_LT(static_cast<int>(touching.size()), bar.m);
  std::vector<std::shared_ptr<const EnergyTerm>> restricted{
      std::make_shared<ElasticTerm<3>>(bar.mesh, make_material<3>(MaterialKind::neo_hookean), 0, bar.m,
                                       touching),
      bar.terms[1]};
  std::vector<Handle> handles;
  for (int h = 0; h < bar.objective->num_handles(); ++h) handles.push_back(bar.objective->handle(h));
  const HandleObjective local(restricted, static_cast<int>(bar.rest.size()), 3, handles, bar.handle_offset,
                              HandleObjectiveOptions{0.7, 2.5});
  const Vector p = bar.design_map()->apply(bar.design(67));
  const Vector x = bar.rest + random_vector(bar.rest.size(), 71, 0.02);
  const double value = bar.objective->value(x, p);
  EXPECT_NEAR(local.value(x, p), value, 1e-12 * value);
  const Vector gx = testing::gradient_x(*bar.objective, x, p), gp = testing::gradient_p(*bar.objective, x, p);
  EXPECT_LE((testing::gradient_x(local, x, p) - gx).norm(), 1e-12 * gx.norm());
  EXPECT_LE((testing::gradient_p(local, x, p) - gp).norm(), 1e-12 * gp.norm());
}

TEST(HandleObjective, RejectsBadHandles) {
  HandleBar bar(MaterialKind::linear);
  const int n = static_cast<int>(bar.rest.size());
  auto make = [&](Handle h) { return HandleObjective(bar.terms, n, 3, {std::move(h)}, bar.handle_offset); };
  Handle none;
  none.vertices = {5};
  EXPECT_THROW(make(none), std::invalid_argument);  // no target
  Handle wrong = none;
  wrong.target_force = Vector::Ones(2);
  EXPECT_THROW(make(wrong), std::invalid_argument);  // force of the wrong size
  Handle repeated = none;
  repeated.vertices = {5, 5};
  repeated.target_force = Vector::Ones(3);
  EXPECT_THROW(make(repeated), std::invalid_argument);
  Handle outside = repeated;
  outside.vertices = {n};
  EXPECT_THROW(make(outside), std::invalid_argument);
  Handle negative = none;
  negative.target_force = Vector::Ones(3);
  negative.weight = -1;
  EXPECT_THROW(make(negative), std::invalid_argument);
}

// Taylor tests of J(z), z = [log E, u~], along E only, u~ only, and both.
void expect_taylor_rates(MaterialKind kind, const char* label) {
  HandleBar bar(kind);
  auto f = bar.functional();
  const Vector z = bar.design(73);
  const Vector all = random_vector(z.size(), 79);
  Vector moduli = all, displacements = all;
  moduli.tail(bar.objective->displacement_size()).setZero();
  displacements.head(bar.m).setZero();
  const std::pair<const char*, Vector> directions[] = {
      {"E", moduli}, {"u~", displacements}, {"E and u~", all}};
  for (const auto& [name, direction] : directions) {
    TaylorTestOptions options;
    options.direction = direction.cwiseProduct(z.cwiseAbs().cwiseMax(0.01));
    const TaylorTestResult t = taylor_test(*f, z, options);
    std::printf("%s, direction %s: rate %.3f\n%s", label, name, t.rate1, t.table().c_str());
    EXPECT_TRUE(t.passed()) << label << ", " << name << "\n" << t.table();
    EXPECT_GE(t.rate1, 1.9);
  }
}

TEST(HandleObjective, TaylorTestLinear) { expect_taylor_rates(MaterialKind::linear, "linear"); }
TEST(HandleObjective, TaylorTestNeoHookean) { expect_taylor_rates(MaterialKind::neo_hookean, "neo_hookean"); }

}  // namespace
}  // namespace tailor::handle_objective_test
