#include "forward/solve/newton.hpp"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <limits>

#include "../../support/quadratic_term.hpp"

namespace tailor::newton_test {
namespace {

using testing::QuadraticTerm;

TEST(Newton, QuadraticConvergesInOneStep) {
  const int n = 40;
  const SparseMatrix A = testing::random_spd(n, 11);
  const Vector b = Vector::LinSpaced(n, -2.0, 3.0);
  Model model(n);
  model.add(std::make_unique<QuadraticTerm>(A, b));
  NewtonSolver solver(model);
  Vector y = Vector::Zero(n);
  const NewtonResult r = solver.solve(Vector(), y);
  ASSERT_TRUE(r.converged()) << r.report();
  EXPECT_EQ(r.iterations, 1);
  const Vector x_true = Eigen::SimplicialLDLT<SparseMatrix>(A).solve(b);
  EXPECT_LT((y - x_true).norm(), 1e-10 * x_true.norm());
}

TEST(Newton, CubicConvergesWithDirichletAndReportsHistory) {
  // E = 1/2 x^T A x - b^T x + c/3 sum x^3 is convex near 0 for small c; fix two DOFs.
  const int n = 30;
  const SparseMatrix A = testing::random_spd(n, 5);
  Model model(n);
  model.add(std::make_unique<QuadraticTerm>(A, Vector::Constant(n, 1.0)));
  Vector values = Vector::Zero(n);
  values[0] = 0.1;
  model.set_elimination(Elimination::dirichlet({0, 7}, values));
  NewtonOptions options;
  options.hessian = NewtonHessian::exact;
  NewtonSolver solver(model, options);
  Vector y = Vector::Zero(model.elimination().num_free());
  Vector p(1);
  p[0] = 0.3;
  const NewtonResult r = solver.solve(p, y);
  ASSERT_TRUE(r.converged()) << r.report();
  const Vector g = model.elimination().reduce(model.gradient(model.elimination().expand(y), p));
  EXPECT_LE(g.norm(), options.relative_tolerance * r.initial_residual);
  EXPECT_EQ(static_cast<int>(r.history.size()), r.iterations);
  // Quadratic convergence: the last residuals fall faster than linearly.
  ASSERT_GE(r.history.size(), 3u);
  const auto& h = r.history;
  EXPECT_LT(r.final_residual / h.back().residual, h.back().residual / h[h.size() - 2].residual);
}

// An energy that becomes NaN away from the start: Newton must report, not abort.
class NanTerm final : public EnergyTerm {
 public:
  std::string name() const override { return "nan"; }
  void evaluate(const Vector& x, const Vector&, const EnergyRequest& r) const override {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (r.value) *r.value += x.squaredNorm() < 1.0 ? -x.sum() : nan;
    if (r.gradient) *r.gradient -= Vector::Ones(x.size());
    if (r.hessian_values)
      for (Eigen::Index i = 0; i < x.size(); ++i) r.hessian_values[i] = 0.0;
  }
  void hessian_pattern(HessianPattern& pattern) const override {
    for (int i = 0; i < 3; ++i) pattern.push_back({i, i});
  }
};

TEST(Newton, SingularHessianIsReportedAsStatus) {
  Model model(3);
  model.add(std::make_unique<NanTerm>());
  NewtonSolver solver(model);
  Vector y = Vector::Zero(3);
  const NewtonResult r = solver.solve(Vector(), y);
  EXPECT_FALSE(r.converged());
  EXPECT_FALSE(r.message.empty());
}

TEST(Newton, WrongInitialGuessSizeIsReported) {
  Model model(4);
  model.add(std::make_unique<QuadraticTerm>(testing::random_spd(4, 1), Vector::Ones(4)));
  NewtonSolver solver(model);
  Vector y = Vector::Zero(3);
  const NewtonResult r = solver.solve(Vector(), y);
  EXPECT_FALSE(r.converged());
  EXPECT_NE(r.message.find("unknowns"), std::string::npos);
}

}  // namespace
}  // namespace tailor::newton_test
