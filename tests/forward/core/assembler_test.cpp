#include "forward/core/assembler.hpp"

#include <gtest/gtest.h>

#include "../../support/quadratic_term.hpp"

namespace tailor::assembler_test {
namespace {

using testing::QuadraticTerm;
using testing::random_spd;

// Reduced gradient and Hessian of the assembler must equal S^T g and S^T H S for Dirichlet
// (selection) and for a general basis with merged and weighted DOFs.
void expect_reduction_matches(const Elimination& elimination) {
  const int n = elimination.num_dofs();
  const SparseMatrix A = random_spd(n, 7);
  const Vector b = Vector::LinSpaced(n, -1.0, 2.0);
  Model model(n);
  model.add(std::make_unique<QuadraticTerm>(A, b));
  model.set_elimination(elimination);
  ReducedAssembler assembler(model);
  const Vector y = Vector::LinSpaced(elimination.num_free(), 0.3, -0.7);
  Vector p(1);
  p[0] = 0.25;
  double energy = 0;
  Vector gy;
  SparseMatrix hy = assembler.hessian_pattern_matrix();
  assembler.evaluate(y, p, &energy, &gy, &hy);

  const Vector x = elimination.expand(y);
  const SparseMatrix& S = elimination.basis();
  const SparseMatrix H = model.terms()[0]->hessian(x, p, HessianMode::exact);
  const Matrix expected_h = Matrix(S.transpose() * H * S);
  const Matrix got_h = Matrix(SparseMatrix(hy.selfadjointView<Eigen::Upper>()));
  EXPECT_NEAR(energy, model.energy(x, p), 1e-12 * std::abs(energy));
  EXPECT_LT((gy - S.transpose() * model.gradient(x, p)).norm(), 1e-12 * gy.norm());
  EXPECT_LT((got_h - expected_h).norm(), 1e-12 * expected_h.norm());
  // Re-assembly overwrites rather than accumulates.
  assembler.evaluate(y, p, nullptr, nullptr, &hy);
  EXPECT_LT((Matrix(SparseMatrix(hy.selfadjointView<Eigen::Upper>())) - expected_h).norm(), 1e-12 * expected_h.norm());
}

TEST(ReducedAssembler, DirichletMatchesExplicitProjection) {
  const Vector values = Vector::Constant(12, 0.5);
  expect_reduction_matches(Elimination::dirichlet({0, 5, 11}, values));
}

TEST(ReducedAssembler, GeneralBasisMatchesExplicitProjection) {
  // DOFs 0 and 6 share one unknown (periodicity), DOF 3 is a weighted mix of two unknowns,
  // DOF 9 is fixed.
  const int n = 10;
  Triplets t;
  int column = 0;
  std::vector<int> col_of(n, -1);
  for (int i = 0; i < n; ++i) {
    if (i == 6 || i == 9 || i == 3) continue;
    col_of[i] = column++;
    t.emplace_back(i, col_of[i], 1.0);
  }
  t.emplace_back(6, col_of[0], 1.0);
  t.emplace_back(3, col_of[1], 0.5);
  t.emplace_back(3, col_of[2], -2.0);
  SparseMatrix S(n, column);
  S.setFromTriplets(t.begin(), t.end());
  Vector x0 = Vector::Zero(n);
  x0[9] = 1.5;
  const Elimination e(x0, S);
  EXPECT_FALSE(e.is_selection());
  expect_reduction_matches(e);
}

TEST(ReducedAssembler, LongRowsReducedThroughProductsMatchExplicitProjection) {
  // Rows longer than the short-row limit (DOFs 0-5: each a dense combination of 20 unknowns,
  // like a collocation transformation's rows) take the coupled product; they mix with
  // selection rows, a two-entry row and fixed DOFs, all against the dense S^T H S.
  const int n = 40;
  Triplets t;
  int column = 0;
  std::vector<int> col_of(n, -1);
  for (int i = 6; i < n; ++i) {
    if (i == 17 || i == 23) continue;  // fixed
    col_of[static_cast<std::size_t>(i)] = column++;
    t.emplace_back(i, col_of[static_cast<std::size_t>(i)], 1.0);
  }
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 20; ++k) t.emplace_back(i, (3 * i + k) % column, std::sin(1.0 + i + 0.37 * k));
  t.emplace_back(17, col_of[8], 0.5);
  t.emplace_back(17, col_of[30], -1.5);
  SparseMatrix S(n, column);
  S.setFromTriplets(t.begin(), t.end());
  Vector x0 = Vector::LinSpaced(n, 0.1, 0.9);
  const Elimination e(x0, S);
  EXPECT_FALSE(e.is_selection());
  expect_reduction_matches(e);
}

// E = p0 / 2 x^T A x: a Hessian p0 A that is constant in x; counts how often it is written.
class ScaledQuadratic final : public EnergyTerm {
 public:
  explicit ScaledQuadratic(SparseMatrix A) : A_(std::move(A)) {}
  std::string name() const override { return "scaled quadratic"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& r) const override {
    if (r.value) *r.value += 0.5 * p[0] * x.dot(A_ * x);
    if (r.gradient) *r.gradient += p[0] * (A_ * x);
    if (r.hessian_values) {
      ++writes;
      std::size_t k = 0;
      for (int j = 0; j < A_.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(A_, j); it; ++it) r.hessian_values[k++] = p[0] * it.value();
    }
  }
  void hessian_pattern(HessianPattern& pattern) const override {
    for (int j = 0; j < A_.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A_, j); it; ++it) pattern.push_back({static_cast<int>(it.row()), j});
  }
  bool hessian_is_constant() const override { return true; }
  std::uint64_t hessian_revision() const override { return revision; }
  mutable int writes = 0;
  std::uint64_t revision = 0;

 private:
  SparseMatrix A_;
};

// A constant Hessian is written once per (p, revision, mode); the assembled matrix is always
// the current one (the state-dependent term next to it is re-evaluated every time).
TEST(ReducedAssembler, ConstantHessiansAreKeptWhileParametersAndRevisionHold) {
  const int n = 9;
  Model model(n);
  auto constant = std::make_unique<ScaledQuadratic>(random_spd(n, 3));
  ScaledQuadratic* c = constant.get();
  model.add(std::move(constant));
  model.add(std::make_unique<QuadraticTerm>(random_spd(n, 4), Vector::Ones(n)));  // cubic: not constant
  model.set_elimination(Elimination::dirichlet({2, 7}, Vector::Constant(n, 0.1)));
  ReducedAssembler assembler(model);
  SparseMatrix hy = assembler.hessian_pattern_matrix();
  auto check = [&](const Vector& y, const Vector& p, HessianMode mode, int expected_writes) {
    assembler.evaluate(y, p, nullptr, nullptr, &hy, mode);
    EXPECT_EQ(c->writes, expected_writes);
    const Vector x = model.elimination().expand(y);
    const SparseMatrix& S = model.elimination().basis();
    const SparseMatrix H = model.terms()[0]->hessian(x, p, mode) + model.terms()[1]->hessian(x, p, mode);
    const Matrix expected = Matrix(S.transpose() * H * S);
    const Matrix got = Matrix(SparseMatrix(hy.selfadjointView<Eigen::Upper>()));
    EXPECT_LT((got - expected).norm(), 1e-12 * expected.norm()) << "writes " << expected_writes;
    c->writes = expected_writes;  // the reference Hessian above was a write too
  };
  const Vector y0 = Vector::LinSpaced(n - 2, 0.3, -0.7), y1 = Vector::LinSpaced(n - 2, -0.2, 0.9);
  Vector p(1);
  p[0] = 0.25;
  check(y0, p, HessianMode::exact, 1);
  check(y1, p, HessianMode::exact, 1);  // another state: kept
  assembler.evaluate(y1, p, nullptr, nullptr, nullptr);  // no Hessian asked: nothing changes
  check(y0, p, HessianMode::exact, 1);
  p[0] = 0.5;
  check(y0, p, HessianMode::exact, 2);  // new p
  c->revision = 1;
  check(y0, p, HessianMode::exact, 3);  // new revision (a new time step, say)
  check(y0, p, HessianMode::projected, 4);  // another mode
  check(y1, p, HessianMode::projected, 4);
}

TEST(ParameterLayout, BlocksAreContiguousAndNamed) {
  ParameterLayout layout;
  EXPECT_EQ(layout.add("youngs_modulus", 4), 0);
  EXPECT_EQ(layout.add("poisson_ratio", 4), 4);
  EXPECT_EQ(layout.size(), 8);
  EXPECT_EQ(layout.at("poisson_ratio").offset, 4);
  EXPECT_THROW(layout.add("youngs_modulus", 1), std::invalid_argument);
  EXPECT_THROW(layout.at("density"), std::out_of_range);
}

}  // namespace
}  // namespace tailor::assembler_test
