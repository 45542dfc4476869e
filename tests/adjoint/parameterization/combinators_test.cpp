// compose and embed_blocks: chain rule to second order, and block embedding into a fixed base.
#include "map_checks.hpp"

namespace tailor::combinators_test {
namespace {

using testing::random_vector;

TEST(Compose, TwoNonlinearMapsChainToSecondOrder) {
  // Both chain-rule terms of the second derivative are non-zero here.
  const auto map = compose(exp_map(3), bounds_map(Vector::Constant(3, -1.0), Vector::Constant(3, 2.0)));
  EXPECT_EQ(map->name(), "compose(exp(3), bounds(3))");
  const Vector z = random_vector(3, 1, -1.5, 1.5);
  const Vector inner = bounds_map(Vector::Constant(3, -1.0), Vector::Constant(3, 2.0))->apply(z);
  EXPECT_TRUE(map->apply(z).isApprox(inner.array().exp().matrix(), 1e-15));
  testing::expect_first_order_consistent(*map, z, true);
  testing::expect_second_order_consistent(*map, z);
}

TEST(Compose, ThreeMapsMatchDenseProductAndDifferences) {
  // p = exp(scatter(bounds(z))): nonlinear outside and inside a linear middle map.
  std::vector<int> region(100);
  for (int e = 0; e < 100; ++e) region[e] = e % 4;
  const auto bounds = bounds_map(Vector::Constant(4, -1.0), (Vector(4) << 0.0, 1.0, 2.0, 3.0).finished());
  const auto scatter = region_scatter_map(region, 4);
  const auto map = compose(exp_map(100), compose(scatter, bounds));
  EXPECT_EQ(map->name(), "compose(exp(100), compose(region_scatter(4 -> 100), bounds(4)))");
  EXPECT_EQ(map->num_design(), 4);
  EXPECT_EQ(map->num_params(), 100);
  const Vector z = random_vector(4, 2, -1.0, 1.0);
  const Vector q = scatter->apply(bounds->apply(z));
  const Matrix expected = exp_map(100)->jacobian(q) * scatter->jacobian(z) * bounds->jacobian(z);
  EXPECT_TRUE(map->jacobian(z).isApprox(expected, 1e-14));
  testing::expect_first_order_consistent(*map, z, true);
  testing::expect_second_order_consistent(*map, z);
}

TEST(Compose, LinearMapsComposeToALinearMap) {
  const auto map = compose(linear_basis_map(Matrix::Random(6, 5), random_vector(6, 3)),
                           spline_map(Vector::LinSpaced(3, 0.0, 1.0), Vector::LinSpaced(5, 0.0, 1.0)));
  const Vector z = random_vector(3, 4);
  testing::expect_first_order_consistent(*map, z, false);
  testing::expect_linear_in_z(*map, z);
}

// A two-block parameter vector [Young's moduli (m), Poisson's ratios (m)]: the moduli are
// exp of a spline of log-moduli, the ratios are bounded per region, except the first two,
// which stay at their base values. Blocks are listed in reverse offset order, so z starts
// with the ratio regions.
struct EmbedFixture {
  static constexpr int m = 20;
  Vector base = (Vector(2 * m) << Vector::Constant(m, 1e5), Vector::Constant(m, 0.3)).finished();
  ParameterizationPtr moduli =
      compose(exp_map(m), spline_map(Vector::LinSpaced(5, 0.0, 1.0), Vector::LinSpaced(m, 0.0, 1.0)));
  ParameterizationPtr ratios = compose(region_scatter_map(std::vector<int>(m - 2, 0), 1),
                                       bounds_map(Vector::Constant(1, 0.0), Vector::Constant(1, 0.49)));
  ParameterizationPtr map = embed_blocks(base, {{m + 2, ratios}, {0, moduli}});
  Vector z = (Vector(6) << 0.4, random_vector(5, 5, 10.0, 12.0)).finished();
};

TEST(EmbedBlocks, ReplacesBlockRangesAndKeepsTheRest) {
  EmbedFixture f;
  const int m = EmbedFixture::m;
  EXPECT_EQ(f.map->num_design(), 6);
  EXPECT_EQ(f.map->num_params(), 2 * m);
  EXPECT_EQ(f.map->name(),
            "embed_blocks(40: [22, 40) <- " + f.ratios->name() + ", [0, 20) <- " + f.moduli->name() + ")");
  const Vector p = f.map->apply(f.z);
  EXPECT_EQ(p.head(m), f.moduli->apply(f.z.tail(5)));
  EXPECT_EQ(p.segment(m, 2), f.base.segment(m, 2));
  EXPECT_EQ(p.tail(m - 2), f.ratios->apply(f.z.head(1)));
  // Fixed entries do not respond to the design.
  const Matrix J = f.map->jacobian(f.z);
  EXPECT_EQ(J.middleRows(m, 2), Matrix::Zero(2, 6));
  EXPECT_EQ(J.block(0, 0, m, 1), Matrix::Zero(m, 1));
  EXPECT_EQ(J.block(m + 2, 1, m - 2, 5), Matrix::Zero(m - 2, 5));
}

TEST(EmbedBlocks, DerivativesMatchDifferences) {
  EmbedFixture f;
  testing::expect_first_order_consistent(*f.map, f.z, true);
  testing::expect_second_order_consistent(*f.map, f.z);
  // The moduli (~1e5) dwarf the ratios (~0.3) in a joint check (their errors fall below its
  // round-off floor), so each block is also checked on its own parameter range, along a
  // direction that moves only its own design variables.
  struct Range {
    int design_start, design_size, param_start, param_size;
  };
  const int m = EmbedFixture::m;
  for (const Range r : {Range{0, 1, m + 2, m - 2}, Range{1, 5, 0, m}}) {
    Vector dz = Vector::Zero(6);
    dz.segment(r.design_start, r.design_size) = random_vector(r.design_size, 8);
    const DerivativeCheck c = check_directional_derivative(
        "block",
        [&](double t) -> Vector { return f.map->apply(f.z + t * dz).segment(r.param_start, r.param_size); },
        f.map->jacobian_times(f.z, dz).segment(r.param_start, r.param_size), {});
    EXPECT_TRUE(c.passed) << "block at " << r.param_start << ": " << c.message;
    EXPECT_NEAR(c.observed_order, 2.0, 0.25) << "block at " << r.param_start << ": " << c.message;
  }
  // Block-wise second derivative: the embedded product is the concatenation of the blocks'.
  const Vector w = random_vector(2 * EmbedFixture::m, 6), dz = random_vector(6, 7);
  const Vector second = f.map->second_derivative_times(f.z, w, dz);
  EXPECT_EQ(second.head(1),
            f.ratios->second_derivative_times(f.z.head(1), w.tail(EmbedFixture::m - 2), dz.head(1)));
  EXPECT_EQ(second.tail(5),
            f.moduli->second_derivative_times(f.z.tail(5), w.head(EmbedFixture::m), dz.tail(5)));
}

TEST(EmbedBlocks, ComposesFurther) {
  // The embedded vector fed through one more map: compose(exp, embed(...)) over log-parameters.
  EmbedFixture f;
  const auto log_params =
      embed_blocks(Vector::Zero(2 * EmbedFixture::m), {{0, f.moduli}, {EmbedFixture::m + 2, f.ratios}});
  const auto map =
      compose(identity_map(2 * EmbedFixture::m), compose(exp_map(2 * EmbedFixture::m), log_params));
  const Vector z = (Vector(6) << random_vector(5, 8, 0.0, 1.0), 0.2).finished();
  testing::expect_first_order_consistent(*map, z, true);
  testing::expect_second_order_consistent(*map, z);
}

TEST(EmbedBlocks, NoBlocksIsTheConstantBase) {
  const Vector base = random_vector(4, 9);
  const auto map = embed_blocks(base, {});
  EXPECT_EQ(map->num_design(), 0);
  EXPECT_EQ(map->apply(Vector(0)), base);
  EXPECT_EQ(map->jacobian_times(Vector(0), Vector(0)), Vector::Zero(4));
}

}  // namespace
}  // namespace tailor::combinators_test
