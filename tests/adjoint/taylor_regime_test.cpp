// The Taylor test must establish the asymptotic regime before it judges (adjoint/taylor_test.hpp).
// Scene: a Neo-Hookean bar 6 x 1 x 1 (1,152 tets), clamped at x = 0, bent by a large end
// traction (tip deflection ~40% of its length); design: per-element log E (1,152 variables);
// objective: target positions on a third of the vertices, 0.05% beyond the equilibrium at the
// design (near an optimum, as late in an optimization: small gradient, full curvature). At the
// default first step (1% of |log E| ~ 0.14 per entry) the second-order term dominates every
// row here, so a fixed-step test that trusted the rate would pass wrong gradients; the
// adaptive test must pass the exact gradient and fail the gradient scaled by 0.5 or 1.5 or
// with one block zeroed, and the same for Hessian-vector products.
#include <gtest/gtest.h>

#include "../support/fem_fixtures.hpp"
#include "../support/inverse_fixtures.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/loads.hpp"

namespace tailor::taylor_regime_test {
namespace {

using namespace tailor::testing;

struct BentBar {
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(6, 1, 1), 12, 4, 4);
  Model model{3 * mesh.num_vertices()};
  Vector rest, p0, target;
  std::vector<int> observed;
  BentBar() {
    const int m = mesh.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<3>(mesh, MaterialKind::neo_hookean));
    const Eigen::MatrixXi end =
        boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[0] > 6 - 1e-9; });
    model.add(std::make_unique<ExternalForceTerm>(traction_forces(mesh, end, Eigen::Vector3d(0, 2e3, -1e4))));
    rest = rest_state(mesh);
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.rest_positions(v, 0) < 1e-9)
        for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
      else if (v % 3 == 0)
        for (int k = 0; k < 3; ++k) observed.push_back(3 * v + k);
    }
    model.set_elimination(Elimination::dirichlet(fixed, rest));
    p0 = heterogeneous_parameters(mesh, 1e6, 0.3);
    target = Vector::Zero(static_cast<Eigen::Index>(observed.size()));
    StaticFunctional probe = functional();
    probe.value(z0());
    for (std::size_t k = 0; k < observed.size(); ++k) {
      const int d = observed[k];
      target[static_cast<Eigen::Index>(k)] = probe.state()[d] + 5e-4 * (probe.state()[d] - rest[d]);
    }
  }
  StaticFunctional functional() {
    const int m = mesh.num_elements();
    return StaticFunctional(model, std::make_shared<LogModuliMap>(p0, m),
                            std::make_shared<DofTargetObjective>(observed, target),
                            model.elimination().restrict_state(rest));
  }
  Vector z0() const { return p0.head(mesh.num_elements()).array().log().matrix(); }
};

// Scales the gradient (and the Hessian-vector product) by `scale`, after zeroing the entries
// in [zero_begin, zero_end).
class Distorted final : public ReducedFunctional {
 public:
  Distorted(ReducedFunctional& inner, double scale, int zero_begin = 0, int zero_end = 0,
            bool hessian_only = false)
      : inner_(inner), scale_(scale), begin_(zero_begin), end_(zero_end), hessian_only_(hessian_only) {}
  int size() const override { return inner_.size(); }
  double value(const Vector& z) override { return inner_.value(z); }
  double value_and_gradient(const Vector& z, Vector& g) override {
    const double j = inner_.value_and_gradient(z, g);
    if (!hessian_only_) distort(g);
    return j;
  }
  bool has_hessian_vector() const override { return inner_.has_hessian_vector(); }
  Vector hessian_vector(const Vector& z, const Vector& v) override {
    Vector hv = inner_.hessian_vector(z, v);
    distort(hv);
    return hv;
  }

 private:
  void distort(Vector& g) const {
    g.segment(begin_, end_ - begin_).setZero();
    g *= scale_;
  }
  ReducedFunctional& inner_;
  double scale_;
  int begin_, end_;
  bool hessian_only_;
};

class TaylorRegime : public ::testing::Test {
 protected:
  static BentBar& bar() {
    static BentBar instance;
    return instance;
  }
};

TEST_F(TaylorRegime, ExactGradientPassesInTheAsymptoticRegime) {
  StaticFunctional f = bar().functional();
  const TaylorTestResult t = taylor_test(f, bar().z0());
  ASSERT_TRUE(t.passed()) << t.table();
  EXPECT_NEAR(t.rate0, 1.0, 0.1) << t.table();
  EXPECT_LT(t.step, 1e-2) << t.table();  // the search had to shrink the step first
}

TEST_F(TaylorRegime, AFixedStepWouldHavePassedAWrongGradient) {
  // The old behaviour: judge the rows from h = 1e-2 without the regime search. The gradient
  // scaled by 1.5 then shows a second-order rate, which is why the search exists.
  StaticFunctional f = bar().functional();
  Distorted wrong(f, 1.5);
  TaylorTestOptions fixed;
  fixed.asymptotic_fraction = 1e30;  // accept any step as asymptotic
  fixed.first_rate_tolerance = 1e30;
  const TaylorTestResult t = taylor_test(wrong, bar().z0(), fixed);
  EXPECT_GT(t.rate1, 1.5) << t.table();
}

TEST_F(TaylorRegime, ScaledOrPartlyZeroedGradientsFail) {
  const int m = bar().mesh.num_elements();
  for (const auto& [scale, begin, end] :
       {std::tuple{0.5, 0, 0}, std::tuple{1.5, 0, 0}, std::tuple{1.0, 0, m / 2}}) {
    StaticFunctional f = bar().functional();
    Distorted wrong(f, scale, begin, end);
    const TaylorTestResult t = taylor_test(wrong, bar().z0());
    EXPECT_FALSE(t.passed()) << "scale " << scale << ", zeroed [" << begin << ", " << end << ")\n"
                             << t.table();
  }
}

TEST_F(TaylorRegime, HessianVectorProducts) {
  StaticFunctional f = bar().functional();
  ASSERT_TRUE(f.has_hessian_vector());
  const TaylorTestResult exact = taylor_test_hessian(f, bar().z0());
  EXPECT_TRUE(exact.passed()) << exact.table();
  for (double scale : {0.5, 1.5}) {
    StaticFunctional g = bar().functional();
    Distorted wrong(g, scale, 0, 0, true);
    const TaylorTestResult t = taylor_test_hessian(wrong, bar().z0());
    EXPECT_FALSE(t.passed()) << "Hessian scaled by " << scale << "\n" << t.table();
  }
}

}  // namespace
}  // namespace tailor::taylor_regime_test
