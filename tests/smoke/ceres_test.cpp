#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>

namespace tailor::ceres_test {
namespace {

// Residual of the model y = exp(m t + c) at one sample.
struct ExponentialResidual {
  double t, y;
  template <typename T>
  bool operator()(const T* m, const T* c, T* residual) const {
    residual[0] = T(y) - ceres::exp(m[0] * T(t) + c[0]);
    return true;
  }
};

TEST(smoke, CeresFitsExponentialToExactData) {
  const double true_m = 0.3, true_c = 0.1;
  double m = 0.0, c = 0.0;
  ceres::Problem problem;
  for (int k = 0; k < 20; ++k) {
    const double t = 0.25 * k;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ExponentialResidual, 1, 1, 1>(
                                 new ExponentialResidual{t, std::exp(true_m * t + true_c)}),
                             nullptr, &m, &c);
  }
  ceres::Solver::Options options;
  options.logging_type = ceres::SILENT;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-15;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_NEAR(m, true_m, 1e-9);
  EXPECT_NEAR(c, true_c, 1e-9);
  EXPECT_LT(summary.final_cost, 1e-20);
}

// Rosenbrock with its analytic gradient; minimum 0 at (1, 1).
class Rosenbrock : public ceres::FirstOrderFunction {
 public:
  int NumParameters() const override { return 2; }
  bool Evaluate(const double* x, double* cost, double* gradient) const override {
    const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
    cost[0] = a * a + 100.0 * b * b;
    if (gradient != nullptr) {
      gradient[0] = -2.0 * a - 400.0 * x[0] * b;
      gradient[1] = 200.0 * b;
    }
    return true;
  }
};

TEST(smoke, CeresGradientProblemLbfgsMinimizesRosenbrock) {
  double x[2] = {-1.2, 1.0};
  const ceres::GradientProblem problem(new Rosenbrock());
  ceres::GradientProblemSolver::Options options;
  options.line_search_direction_type = ceres::LBFGS;
  options.logging_type = ceres::SILENT;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-16;
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(options, problem, x, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_NEAR(x[0], 1.0, 1e-6);
  EXPECT_NEAR(x[1], 1.0, 1e-6);
}

}  // namespace
}  // namespace tailor::ceres_test
