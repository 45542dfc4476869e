// The rod strains on Dual0 (values), Dual1<N> (values and gradients) and Dual2<N> (and Hessians)
// agree bit for bit on what they share, in the stencil's 11 DOFs and in the 8 edge variables
// the terms use (whose lifted derivatives agree with the direct ones to round-off) (forward/rods/low_order_duals.hpp): an energy request, a
// gradient request and a Hessian assembly see the same function to the last bit (reference:
// the Dual2 path, which the derivative checks of rod_derivatives_test.cpp hold against central
// differences). A bent, twisted helix with frames stored ~0.3 rad away and perturbed parameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_stencils.hpp"
#include "rod_fixtures.hpp"

namespace tailor::rod_scalar_orders_test {
namespace {

using namespace tailor::testing;

struct Evaluation {
  double value = 0.0;
  Vector gradient;
};

Evaluation evaluate(const EnergyTerm& term, const Vector& x, const Vector& p, bool gradient, bool hessian) {
  Evaluation e;
  e.gradient = Vector::Zero(x.size());
  HessianPattern pattern;
  term.hessian_pattern(pattern);
  std::vector<double> h(pattern.size());
  EnergyRequest request;
  request.value = &e.value;
  request.gradient = gradient ? &e.gradient : nullptr;
  request.hessian_values = hessian ? h.data() : nullptr;
  term.evaluate(x, p, request);
  return e;
}

TEST(RodScalarOrders, EnergyAndGradientPathsAgreeBitForBit) {
  RodSetup s = make_rod(helix(30, 1.0, 0.2, 1.3));
  s.rod->update_reference_frames(s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 3));
  const Vector x = s.rest + 0.2 * uniform_noise(s.model->num_dofs(), 4);
  Vector p = s.p;
  p.array() *= 1.0 + 0.2 * uniform_noise(static_cast<int>(p.size()), 5).array();
  for (const EnergyTerm* term :
       std::initializer_list<const EnergyTerm*>{s.stretching, s.bending, s.twisting}) {
    const Evaluation value_only = evaluate(*term, x, p, false, false);
    const Evaluation first = evaluate(*term, x, p, true, false);
    const Evaluation second = evaluate(*term, x, p, true, true);
    EXPECT_EQ(value_only.value, second.value) << term->name();
    EXPECT_EQ(first.value, second.value) << term->name();
    EXPECT_EQ((first.gradient - second.gradient).lpNorm<Eigen::Infinity>(), 0.0) << term->name();
    EXPECT_GT(second.gradient.norm(), 0.0) << term->name();
  }
  // The switch rod_bench uses for its "before" runs gives the same numbers.
  s.bending->set_first_order_path(false);
  const Evaluation old_path = evaluate(*s.bending, x, p, true, false);
  s.bending->set_first_order_path(true);
  EXPECT_EQ((old_path.gradient - evaluate(*s.bending, x, p, true, false).gradient).lpNorm<Eigen::Infinity>(), 0.0);
}

TEST(RodScalarOrders, StrainsAgreeBitForBitAtEveryStencil) {
  RodSetup s = make_rod(helix(12, 1.0, 0.3, 0.9));
  s.rod->update_reference_frames(s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 6));
  const Vector x = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 7);
  for (int i = 0; i < s.rod->num_interior(); ++i) {
    const auto dofs = rod_detail::bend_twist_dofs(*s.rod, i);
    rod_detail::BendTwistLocal local;
    for (int r = 0; r < rod_detail::kBendTwistDofs; ++r) local[r] = x[dofs[static_cast<std::size_t>(r)]];
    const auto frames = rod_detail::stored_frames(*s.rod, i);
    const auto s2 = rod_detail::bend_twist_strains<rod_detail::BendTwistDual>(local, frames);
    const auto s1 = rod_detail::bend_twist_strains<rod_detail::BendTwistDual1>(local, frames);
    const auto s0 = rod_detail::bend_twist_strains<rod_detail::Dual0>(local, frames);
    EXPECT_EQ(s0.kappa1.v, s2.kappa1.v);
    EXPECT_EQ(s0.kappa2.v, s2.kappa2.v);
    EXPECT_EQ(s0.twist.v, s2.twist.v);
    EXPECT_EQ(s1.kappa1.v, s2.kappa1.v);
    EXPECT_EQ(s1.twist.v, s2.twist.v);
    EXPECT_EQ((s1.kappa1.g - s2.kappa1.g).lpNorm<Eigen::Infinity>(), 0.0) << i;
    EXPECT_EQ((s1.kappa2.g - s2.kappa2.g).lpNorm<Eigen::Infinity>(), 0.0) << i;
    EXPECT_EQ((s1.twist.g - s2.twist.g).lpNorm<Eigen::Infinity>(), 0.0) << i;
    // The terms' path: derivatives in the two edges and twists, lifted to the 11 DOFs.
    using E2 = Dual2<rod_detail::kEdgeVariables>;
    using E1 = rod_detail::Dual1<rod_detail::kEdgeVariables>;
    const auto e2 = rod_detail::curvatures_by_edges<Dual2<3>, Dual2<6>, E2>(local, frames);
    const auto e1 = rod_detail::curvatures_by_edges<rod_detail::Dual1<3>, rod_detail::Dual1<6>, E1>(local, frames);
    EXPECT_EQ(e2[0].v, s0.kappa1.v);
    EXPECT_EQ(e2[1].v, s0.kappa2.v);
    EXPECT_EQ(e1[1].v, s0.kappa2.v);
    EXPECT_EQ((rod_detail::lift(e1[0]).g - rod_detail::lift(e2[0]).g).lpNorm<Eigen::Infinity>(), 0.0);
    EXPECT_EQ((rod_detail::lift(e1[1]).g - rod_detail::lift(e2[1]).g).lpNorm<Eigen::Infinity>(), 0.0);
    // The twisting term's path: the reference twist in the 6 edge coordinates.
    const auto w2 = rod_detail::twist_from_reference(rod_detail::reference_twist_by_edges<Dual2<3>, Dual2<6>>(local, frames), local);
    const auto w1 =
        rod_detail::twist_from_reference(rod_detail::reference_twist_by_edges<rod_detail::Dual1<3>, rod_detail::Dual1<6>>(local, frames), local);
    EXPECT_EQ(w2.v, s0.twist.v);
    EXPECT_EQ(w1.v, s0.twist.v);
    EXPECT_EQ((w1.g - w2.g).lpNorm<Eigen::Infinity>(), 0.0);
    // ... and equal to the direct derivatives to round-off.
    for (const auto& [lifted, direct] : {std::pair{rod_detail::lift(e2[0]), s2.kappa1},
                                         std::pair{rod_detail::lift(e2[1]), s2.kappa2}, std::pair{w2, s2.twist}}) {
      EXPECT_LE((lifted.g - direct.g).lpNorm<Eigen::Infinity>(), 1e-13 * (1.0 + direct.g.lpNorm<Eigen::Infinity>()));
      EXPECT_LE((lifted.h - direct.h).lpNorm<Eigen::Infinity>(), 1e-12 * (1.0 + direct.h.lpNorm<Eigen::Infinity>()));
    }
  }
}

// The Hessian path of the bending and twisting terms (forward/rods/cross_edge_products.hpp:
// the strains' Hessians from dot products of the two edges' frames) against the dual-number
// path (`strains`, the formulas of rod_kinematics.hpp differentiated as written), stencil by
// stencil with independent weights per strain, on stale frames: equal to round-off, so a
// dropped or mis-signed block (the cross-edge block h01, a product's own Hessians, the chain
// term dp^T f_pp dp, the theta rows of the material frame) fails. The derivative checks of
// rod_derivatives_test.cpp hold the terms' Hessians, by this path, against central differences.
TEST(RodScalarOrders, CrossEdgeProductHessiansMatchTheDualPath) {
  RodSetup s = make_rod(helix(14, 1.0, 0.3, 0.9));
  s.rod->update_reference_frames(s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 8));
  Vector x = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 9);
  for (int j = 0; j < s.rod->num_edges(); ++j) x[s.rod->twist_dof(j)] += 0.7 * j;  // turned material frames
  s.bending->prepare(x, rod_detail::kProductHessians);
  s.twisting->prepare(x, rod_detail::kProductHessians);
  double worst = 0.0;
  for (int i = 0; i < s.rod->num_interior(); ++i) {
    const auto dofs = rod_detail::bend_twist_dofs(*s.rod, i);
    rod_detail::BendTwistLocal local;
    for (int r = 0; r < rod_detail::kBendTwistDofs; ++r) local[r] = x[dofs[static_cast<std::size_t>(r)]];
    const Eigen::Vector2d w(1.0 + 0.1 * i, -0.6 + 0.05 * i);
    const auto kappa = s.bending->strains(local, i);
    const Eigen::Matrix<double, 11, 11> bending_dual = w[0] * kappa[0].h + w[1] * kappa[1].h;
    const Eigen::Matrix<double, 11, 11> bending_products = s.bending->strain_hessian_sum(local, i, w);
    const double scale_b = bending_dual.lpNorm<Eigen::Infinity>();
    EXPECT_GT(scale_b, 1e-3);
    EXPECT_LE((bending_products - bending_dual).lpNorm<Eigen::Infinity>(), 1e-12 * scale_b) << "stencil " << i;
    const auto twist = s.twisting->strains(local, i);
    const Eigen::Matrix<double, 1, 1> v(0.8 - 0.03 * i);
    const Eigen::Matrix<double, 11, 11> twisting_dual = v[0] * twist[0].h;
    const Eigen::Matrix<double, 11, 11> twisting_products = s.twisting->strain_hessian_sum(local, i, v);
    const double scale_t = twisting_dual.lpNorm<Eigen::Infinity>();
    EXPECT_GT(scale_t, 1e-3);
    EXPECT_LE((twisting_products - twisting_dual).lpNorm<Eigen::Infinity>(), 1e-12 * scale_t) << "stencil " << i;
    worst = std::max({worst, (bending_products - bending_dual).lpNorm<Eigen::Infinity>() / scale_b,
                      (twisting_products - twisting_dual).lpNorm<Eigen::Infinity>() / scale_t});
  }
  std::printf("cross-edge product Hessians vs dual path: largest relative difference %.2e\n", worst);
  // Through the terms: the same energy and gradient bit for bit, the Hessian to round-off.
  Vector p = s.p;
  p.array() *= 1.0 + 0.2 * uniform_noise(static_cast<int>(p.size()), 10).array();
  for (auto* term : std::initializer_list<EnergyTerm*>{s.bending, s.twisting}) {
    HessianPattern pattern;
    term->hessian_pattern(pattern);
    std::vector<double> products(pattern.size()), dual(pattern.size());
    auto assemble = [&](std::vector<double>& h, Vector& g) {
      double value = 0.0;
      g = Vector::Zero(x.size());
      EnergyRequest request;
      request.value = &value;
      request.gradient = &g;
      request.hessian_values = h.data();
      term->evaluate(x, p, request);
      return value;
    };
    Vector g_products, g_dual;
    const double e_products = assemble(products, g_products);
    if (auto* b = dynamic_cast<RodBendingTerm*>(term)) b->set_product_hessian(false);
    if (auto* t = dynamic_cast<RodTwistingTerm*>(term)) t->set_product_hessian(false);
    const double e_dual = assemble(dual, g_dual);
    EXPECT_EQ(e_products, e_dual) << term->name();
    EXPECT_EQ((g_products - g_dual).lpNorm<Eigen::Infinity>(), 0.0) << term->name();
    const Eigen::Map<const Eigen::VectorXd> hp(products.data(), static_cast<Eigen::Index>(products.size())),
        hd(dual.data(), static_cast<Eigen::Index>(dual.size()));
    EXPECT_LE((hp - hd).lpNorm<Eigen::Infinity>(), 1e-12 * hd.lpNorm<Eigen::Infinity>()) << term->name();
  }
}

}  // namespace
}  // namespace tailor::rod_scalar_orders_test
