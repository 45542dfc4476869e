#include <gtest/gtest.h>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>
#include <algorithm>
#include <array>

namespace tailor::ipopt_test {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// Hock-Schittkowski problem 71:
//   min  x1 x4 (x1 + x2 + x3) + x3
//   s.t. x1 x2 x3 x4 >= 25,  x1^2 + x2^2 + x3^2 + x4^2 = 40,  1 <= x <= 5,
// from x0 = (1, 5, 5, 1). Optimum f* = 17.0140173 at x* = (1, 4.7429994, 3.8211503, 1.3794082).
class Hs071 : public Ipopt::TNLP {
 public:
  std::array<double, 4> solution{};
  double objective = 0.0;
  Ipopt::SolverReturn status = Ipopt::INTERNAL_ERROR;

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = 4;
    m = 2;
    nnz_jac_g = 8;   // both constraints are dense in x
    nnz_h_lag = 10;  // lower triangle of a dense 4x4
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index /*m*/, Number* g_l, Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = 1.0;
      x_u[i] = 5.0;
    }
    g_l[0] = 25.0;
    g_u[0] = 2e19;  // above Ipopt's nlp_upper_bound_inf (1e19): no upper bound
    g_l[1] = g_u[1] = 40.0;
    return true;
  }

  bool get_starting_point(Index, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                          bool init_lambda, Number*) override {
    if (!init_x || init_z || init_lambda) return false;
    const double start[4] = {1.0, 5.0, 5.0, 1.0};
    std::copy(start, start + 4, x);
    return true;
  }

  bool eval_f(Index, const Number* x, bool, Number& f) override {
    f = x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2];
    return true;
  }

  bool eval_grad_f(Index, const Number* x, bool, Number* grad) override {
    grad[0] = x[3] * (2 * x[0] + x[1] + x[2]);
    grad[1] = x[0] * x[3];
    grad[2] = x[0] * x[3] + 1.0;
    grad[3] = x[0] * (x[0] + x[1] + x[2]);
    return true;
  }

  bool eval_g(Index, const Number* x, bool, Index, Number* g) override {
    g[0] = x[0] * x[1] * x[2] * x[3];
    g[1] = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3];
    return true;
  }

  bool eval_jac_g(Index, const Number* x, bool, Index, Index, Index* rows, Index* cols,
                  Number* values) override {
    if (values == nullptr) {
      for (Index k = 0; k < 8; ++k) {
        rows[k] = k / 4;
        cols[k] = k % 4;
      }
      return true;
    }
    values[0] = x[1] * x[2] * x[3];
    values[1] = x[0] * x[2] * x[3];
    values[2] = x[0] * x[1] * x[3];
    values[3] = x[0] * x[1] * x[2];
    for (Index i = 0; i < 4; ++i) values[4 + i] = 2.0 * x[i];
    return true;
  }

  // Hessian of sigma f + lambda0 g0 + lambda1 g1, lower triangle in row-major order.
  bool eval_h(Index, const Number* x, bool, Number sigma, Index, const Number* lambda, bool, Index,
              Index* rows, Index* cols, Number* values) override {
    if (values == nullptr) {
      for (Index i = 0, k = 0; i < 4; ++i) {
        for (Index j = 0; j <= i; ++j, ++k) {
          rows[k] = i;
          cols[k] = j;
        }
      }
      return true;
    }
    double h[4][4] = {};
    h[0][0] = sigma * 2 * x[3];
    h[1][0] = sigma * x[3];
    h[2][0] = sigma * x[3];
    h[3][0] = sigma * (2 * x[0] + x[1] + x[2]);
    h[3][1] = sigma * x[0];
    h[3][2] = sigma * x[0];
    h[1][0] += lambda[0] * x[2] * x[3];
    h[2][0] += lambda[0] * x[1] * x[3];
    h[2][1] += lambda[0] * x[0] * x[3];
    h[3][0] += lambda[0] * x[1] * x[2];
    h[3][1] += lambda[0] * x[0] * x[2];
    h[3][2] += lambda[0] * x[0] * x[1];
    for (Index i = 0; i < 4; ++i) h[i][i] += 2.0 * lambda[1];
    for (Index i = 0, k = 0; i < 4; ++i)
      for (Index j = 0; j <= i; ++j, ++k) values[k] = h[i][j];
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn return_status, Index, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number obj_value,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    status = return_status;
    objective = obj_value;
    for (int i = 0; i < 4; ++i) solution[i] = x[i];
  }
};

TEST(smoke, IpoptSolvesHs071WithMumps) {
  Ipopt::SmartPtr<Hs071> problem = new Hs071();
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");  // no banner
  // Debian's Ipopt 3.11 has MUMPS only; other solvers are accepted here and fail at solve time.
  app->Options()->SetStringValue("linear_solver", "mumps");
  app->Options()->SetNumericValue("tol", 1e-10);
  ASSERT_EQ(app->Initialize(), Ipopt::Solve_Succeeded);

  const Ipopt::ApplicationReturnStatus status =
      app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(GetRawPtr(problem)));
  ASSERT_EQ(status, Ipopt::Solve_Succeeded);
  EXPECT_EQ(problem->status, Ipopt::SUCCESS);
  EXPECT_NEAR(problem->objective, 17.0140173, 1e-6);
  const std::array<double, 4> expected = {1.0, 4.7429994, 3.8211503, 1.3794082};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(problem->solution[i], expected[i], 1e-6) << "x" << i + 1;
}

}  // namespace
}  // namespace tailor::ipopt_test
