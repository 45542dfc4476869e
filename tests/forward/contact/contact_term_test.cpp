// ContactTerm over vertex DOFs: check_energy_term with active contact in every branch
// (point-triangle interior, edge-edge crossing, mollified nearly parallel edges, a box
// corner on a floor), PSD projection, the pattern guard, and CCD-limited steps.
#include "forward/contact/contact_term.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "forward/core/symmetric_eigen.hpp"

namespace tailor::contact_term_test {
namespace {

using contact::ContactOptions;
using contact::ContactSurface;

Vector flatten(const contact::Positions& x) {
  Vector v(3 * x.rows());
  for (int i = 0; i < x.rows(); ++i) v.segment<3>(3 * i) = x.row(i).transpose();
  return v;
}
std::vector<int> interleaved_dofs(int n) {
  std::vector<int> dofs(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) dofs[static_cast<std::size_t>(i)] = 3 * i;
  return dofs;
}

ContactOptions options(double d_hat = 0.1, double kappa = 10.0) {
  ContactOptions o;
  o.activation_distance = d_hat;
  o.stiffness = kappa;
  return o;
}

DerivativeCheckOptions small_steps() {
  DerivativeCheckOptions o;
  o.state_scale = 1e-3;  // perturbations of 1e-6 keep every pair in its branch
  return o;
}

void expect_passes(const EnergyTerm& term, const Vector& x) {
  const EnergyTermCheck check = check_energy_term(term, x, Vector(), small_steps());
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
  for (const auto& c : check.checks) EXPECT_FALSE(c.vanishing) << c.quantity;
}

// Two triangles: the tip of the upper one 0.05 above the interior of the lower one.
TEST(ContactTerm, PointTriangleContactPassesDerivativeChecks) {
  contact::Positions x(6, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0,  //
      0.2, 0.2, 0.05, 0.6, 0.25, 0.3, 0.25, 0.6, 0.3;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  const Vector state = flatten(x);
  ContactTerm term(ContactSurface::from_faces(6, faces), interleaved_dofs(6), state, options());
  EXPECT_EQ(term.potential().num_active(x), 1);
  EXPECT_GT(term.value(state, Vector()), 0.0);
  expect_passes(term, state);
}

// Edges only (a rod-like surface): crossing, then nearly parallel (mollified).
TEST(ContactTerm, EdgeEdgeContactPassesDerivativeChecksMollifiedOrNot) {
  Eigen::MatrixX2i edges(2, 2);
  edges << 0, 1, 2, 3;
  const ContactSurface surface = ContactSurface::from_faces(4, Eigen::MatrixX3i(0, 3), {}, edges);
  contact::Positions crossing(4, 3), parallel(4, 3);
  crossing << 0, 0, 0, 1, 0, 0, 0.5, -0.5, 0.05, 0.5, 0.5, 0.06;
  parallel << 0, 0, 0, 1, 0, 0, 0.2, -0.005, 0.05, 0.8, 0.005, 0.05;
  for (const contact::Positions* x : {&crossing, &parallel}) {
    const Vector state = flatten(*x);
    ContactTerm term(surface, interleaved_dofs(4), state, options());
    contact::PairDerivatives d;
    const bool mollified = x == &parallel;
    EXPECT_TRUE(contact::pair_barrier(
        contact::PairKind::edge_edge,
        {x->row(0).transpose(), x->row(1).transpose(), x->row(2).transpose(), x->row(3).transpose()}, 0.01,
        term.potential().mollifier_eps({0, 1}), false, d));
    EXPECT_EQ(d.mollified, mollified);
    expect_passes(term, state);
  }
}

// A unit cube with a tilted corner just above a floor square: several pairs of all kinds.
struct CubeOnFloor {
  ContactSurface surface;
  Vector state;
  CubeOnFloor() {
    contact::Positions x(12, 3);
    x.row(0) << -2, -2, 0;
    x.row(1) << 2, -2, 0;
    x.row(2) << 2, 2, 0;
    x.row(3) << -2, 2, 0;
    const Eigen::AngleAxisd tilt(0.3, Eigen::Vector3d(1, 1, 0).normalized());
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d corner((i & 1) - 0.5, ((i >> 1) & 1) - 0.5, ((i >> 2) & 1) - 0.5);
      x.row(4 + i) = (tilt * corner).transpose();
    }
    const double lowest = x.bottomRows(8).col(2).minCoeff();
    x.bottomRows(8).col(2).array() += 0.03 - lowest;
    Eigen::MatrixX3i faces(14, 3);
    faces << 0, 1, 2, 0, 2, 3,                                    // floor
        4, 6, 5, 5, 6, 7, 8, 9, 10, 9, 11, 10, 4, 5, 8, 5, 9, 8,  //
        6, 10, 7, 7, 10, 11, 4, 8, 6, 6, 8, 10, 5, 7, 9, 7, 11, 9;
    surface = ContactSurface::from_faces(12, faces);
    state = flatten(x);
  }
};

TEST(ContactTerm, CubeCornerOnFloorPassesDerivativeChecksAndProjectsToPsd) {
  const CubeOnFloor scene;
  ContactTerm term(scene.surface, interleaved_dofs(12), scene.state, options(0.1, 1.0));
  EXPECT_GE(term.potential().num_active(term.positions(scene.state)), 1);
  expect_passes(term, scene.state);
  const Eigen::MatrixXd exact = Eigen::MatrixXd(term.hessian(scene.state, Vector(), HessianMode::exact));
  const Eigen::MatrixXd projected =
      Eigen::MatrixXd(term.hessian(scene.state, Vector(), HessianMode::projected));
  EXPECT_GE(symmetric_eigenvalues(projected).minCoeff(), -1e-9 * exact.norm());
}

TEST(ContactTerm, SparsePatternMatchesDenseAndGuardsAgainstMissingPairs) {
  const CubeOnFloor scene;
  ContactTerm dense(scene.surface, interleaved_dofs(12), scene.state, options(0.1, 1.0));
  ContactTerm sparse(scene.surface, interleaved_dofs(12), scene.state, options(0.1, 1.0), 0.2);
  const Eigen::MatrixXd a = Eigen::MatrixXd(dense.hessian(scene.state, Vector(), HessianMode::exact));
  const Eigen::MatrixXd b = Eigen::MatrixXd(sparse.hessian(scene.state, Vector(), HessianMode::exact));
  EXPECT_LT((a - b).norm(), 1e-12 * a.norm());
  HessianPattern dense_pattern, sparse_pattern;
  dense.hessian_pattern(dense_pattern);
  sparse.hessian_pattern(sparse_pattern);
  EXPECT_LT(sparse_pattern.size(), dense_pattern.size());
  // Chosen where the cube is far above the floor: contact then falls outside and throws.
  Vector high = scene.state;
  for (int v = 4; v < 12; ++v) high[3 * v + 2] += 1.0;
  ContactTerm stale(scene.surface, interleaved_dofs(12), high, options(0.1, 1.0), 0.2);
  EXPECT_THROW(stale.hessian(scene.state, Vector(), HessianMode::exact), std::runtime_error);
  stale.update_pattern(scene.state);
  EXPECT_NO_THROW(stale.hessian(scene.state, Vector(), HessianMode::exact));
}

TEST(ContactTerm, MaxStepStopsBeforeImpact) {
  const CubeOnFloor scene;
  ContactTerm term(scene.surface, interleaved_dofs(12), scene.state, options(0.01, 1.0));
  Vector down = Vector::Zero(scene.state.size());
  for (int v = 4; v < 12; ++v) down[3 * v + 2] = -0.06;  // the lowest corner (0.03 up) lands at t = 0.5
  const double step = term.max_step(scene.state, down);
  EXPECT_GT(step, 0.3);
  EXPECT_LT(step, 0.5);
  EXPECT_GT(term.potential().min_distance(term.positions(scene.state + step * down), 1.0), 0.0);
  Vector up = -down;
  EXPECT_EQ(term.max_step(scene.state, up), 1.0);
}

TEST(ContactTerm, RejectsBadInput) {
  Eigen::MatrixX3i faces(1, 3);
  faces << 0, 1, 2;
  const ContactSurface surface = ContactSurface::from_faces(3, faces);
  const Vector state = Vector::Zero(9);
  EXPECT_THROW(ContactTerm(surface, {0, 3}, state, options()), std::invalid_argument);
  EXPECT_THROW(ContactTerm(surface, {0, 3, 7}, state, options()), std::invalid_argument);
  EXPECT_THROW(ContactTerm(surface, {0, 3, 6}, state, options(-1.0)), std::invalid_argument);
  EXPECT_THROW(ContactTerm(surface, {0, 3, 6}, state, options(0.1, 0.0)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::contact_term_test

namespace tailor::contact_term_test {
namespace {

// The checks can fail: the same term with its Hessian scaled by 1 + 1e-4 is caught.
class ScaledHessian final : public EnergyTerm {
 public:
  explicit ScaledHessian(const EnergyTerm& inner) : inner_(inner) { inner_.hessian_pattern(pattern_); }
  std::string name() const override { return "scaled_hessian"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    inner_.evaluate(x, p, request);
    if (request.hessian_values)
      for (std::size_t i = 0; i < pattern_.size(); ++i) request.hessian_values[i] *= 1.0 + 1e-4;
  }
  void hessian_pattern(HessianPattern& pattern) const override {
    pattern.insert(pattern.end(), pattern_.begin(), pattern_.end());
  }

 private:
  const EnergyTerm& inner_;
  HessianPattern pattern_;
};

TEST(ContactTerm, PerturbedHessianIsCaught) {
  const CubeOnFloor scene;
  ContactTerm term(scene.surface, interleaved_dofs(12), scene.state, options(0.1, 1.0));
  const ScaledHessian wrong(term);
  const EnergyTermCheck check = check_energy_term(wrong, scene.state, Vector(), small_steps());
  EXPECT_FALSE(check.passed()) << check.table();
}

}  // namespace
}  // namespace tailor::contact_term_test
