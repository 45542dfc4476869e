#include <gtest/gtest.h>

#include <cmath>
#include <nlopt.hpp>
#include <vector>

namespace tailor::nlopt_test {
namespace {

// Rosenbrock: minimum 0 at (1, 1).
double rosenbrock(const std::vector<double>& x, std::vector<double>& grad, void*) {
  const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
  if (!grad.empty()) {
    grad[0] = -2.0 * a - 400.0 * x[0] * b;
    grad[1] = 200.0 * b;
  }
  return a * a + 100.0 * b * b;
}

TEST(smoke, NloptLbfgsMinimizesRosenbrock) {
  nlopt::opt opt(nlopt::LD_LBFGS, 2);
  opt.set_min_objective(rosenbrock, nullptr);
  opt.set_xtol_rel(1e-12);
  opt.set_maxeval(1000);
  std::vector<double> x = {-1.2, 1.0};
  double f = 0.0;
  const nlopt::result result = opt.optimize(x, f);
  EXPECT_GT(result, 0);  // positive codes are successes
  EXPECT_NEAR(x[0], 1.0, 1e-6);
  EXPECT_NEAR(x[1], 1.0, 1e-6);
  EXPECT_LT(f, 1e-12);
}

// min x + y  s.t.  x^2 + y^2 <= 2: the optimum is where the gradient (1, 1) is normal to the
// circle, x = y = -1, f = -2.
double sum(const std::vector<double>& x, std::vector<double>& grad, void*) {
  if (!grad.empty()) grad[0] = grad[1] = 1.0;
  return x[0] + x[1];
}

double outside_disk(const std::vector<double>& x, std::vector<double>& grad, void*) {  // <= 0 inside
  if (!grad.empty()) {
    grad[0] = 2.0 * x[0];
    grad[1] = 2.0 * x[1];
  }
  return x[0] * x[0] + x[1] * x[1] - 2.0;
}

TEST(smoke, NloptSlsqpRespectsNonlinearConstraint) {
  nlopt::opt opt(nlopt::LD_SLSQP, 2);
  opt.set_min_objective(sum, nullptr);
  opt.add_inequality_constraint(outside_disk, nullptr, 1e-12);
  opt.set_lower_bounds(-3.0);
  opt.set_upper_bounds(3.0);
  opt.set_xtol_rel(1e-12);
  opt.set_maxeval(500);
  std::vector<double> x = {0.5, 0.0};
  double f = 0.0;
  const nlopt::result result = opt.optimize(x, f);
  EXPECT_GT(result, 0);
  EXPECT_NEAR(x[0], -1.0, 1e-7);
  EXPECT_NEAR(x[1], -1.0, 1e-7);
  EXPECT_NEAR(f, -2.0, 1e-9);
}

}  // namespace
}  // namespace tailor::nlopt_test
