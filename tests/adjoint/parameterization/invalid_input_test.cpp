// Every factory and product rejects bad input with std::invalid_argument naming the map and
// the problem.
#include "map_checks.hpp"

namespace tailor::invalid_input_test {
namespace {

using testing::expect_invalid;

TEST(InvalidInput, WrongSizedArgumentsNameTheMapAndBothSizes) {
  const auto map = exp_map(3);
  const Vector z3 = Vector::Zero(3), v2 = Vector::Zero(2);
  expect_invalid([&] { map->apply(v2); }, {"exp(3)", "z has size 2", "num_design = 3"});
  expect_invalid([&] { map->jacobian_times(z3, v2); }, {"exp(3)", "dz has size 2"});
  expect_invalid([&] { map->jacobian_times(v2, z3); }, {"exp(3)", "z has size 2"});
  expect_invalid([&] { map->jacobian_transpose_times(z3, v2); },
                 {"exp(3)", "w has size 2", "num_params = 3"});
  expect_invalid([&] { map->second_derivative_times(z3, v2, z3); }, {"exp(3)", "w has size 2"});
  expect_invalid([&] { map->second_derivative_times(z3, z3, v2); }, {"exp(3)", "dz has size 2"});
  expect_invalid([&] { map->jacobian(v2); }, {"exp(3)", "z has size 2"});
  const auto scatter = region_scatter_map({0, 1, 1}, 2);
  expect_invalid([&] { scatter->jacobian_transpose_times(Vector::Zero(2), Vector::Zero(2)); },
                 {"region_scatter(2 -> 3)", "w has size 2", "num_params = 3"});
  const auto composed = compose(exp_map(3), scatter);
  expect_invalid([&] { composed->apply(z3); }, {"compose(exp(3), region_scatter(2 -> 3))", "z has size 3"});
}

TEST(InvalidInput, NegativeSizes) {
  expect_invalid([] { identity_map(-1); }, {"identity_map", "non-negative", "-1"});
  expect_invalid([] { exp_map(-2); }, {"exp_map", "non-negative", "-2"});
  expect_invalid([] { region_scatter_map({}, -1); }, {"region_scatter_map", "num_regions", "-1"});
}

TEST(InvalidInput, LinearBasis) {
  expect_invalid([] { linear_basis_map(Matrix::Zero(4, 2), Vector::Zero(3)); },
                 {"linear_basis_map", "offset has size 3", "4 rows"});
  Matrix bad = Matrix::Zero(2, 2);
  bad(1, 0) = std::nan("");
  expect_invalid([&] { linear_basis_map(bad, Vector::Zero(2)); }, {"linear_basis_map", "non-finite"});
}

TEST(InvalidInput, RegionIndexOutOfRange) {
  expect_invalid(
      [] {
        region_scatter_map({0, 3, 1}, 3);
      },
      {"region_scatter_map", "out of range", "region_of_entry[1] = 3", "< 3"});
  expect_invalid([] { region_scatter_map({0, -1}, 3); }, {"region_scatter_map", "region_of_entry[1] = -1"});
}

TEST(InvalidInput, Bounds) {
  expect_invalid([] { bounds_map(Vector::Zero(2), Vector::Ones(3)); },
                 {"bounds_map", "lower has size 2", "upper has size 3"});
  expect_invalid([] { bounds_map((Vector(2) << 0.0, 1.0).finished(), (Vector(2) << 1.0, 1.0).finished()); },
                 {"bounds_map", "lower must be below upper", "lower[1] = 1", "upper[1] = 1"});
  expect_invalid([] { bounds_map(Vector::Constant(1, 2.0), Vector::Constant(1, 1.0)); }, {"lower[0] = 2"});
  expect_invalid([] { bounds_map(Vector::Zero(1), Vector::Constant(1, INFINITY)); },
                 {"bounds_map", "finite"});
}

TEST(InvalidInput, Spline) {
  expect_invalid([] { spline_map(Vector::Zero(1), Vector::Zero(3)); },
                 {"spline_map", "at least 2 knots", "got 1"});
  expect_invalid([] { spline_map((Vector(3) << 0.0, 2.0, 1.0).finished(), Vector::Zero(3)); },
                 {"spline_map", "strictly increasing", "knots[2] = 1", "knots[1] = 2"});
  expect_invalid([] { spline_map((Vector(3) << 0.0, 1.0, 1.0).finished(), Vector::Zero(3)); },
                 {"strictly increasing", "knots[2] = 1"});
  expect_invalid([] { spline_map((Vector(2) << 0.0, NAN).finished(), Vector::Zero(3)); },
                 {"spline_map", "finite"});
  expect_invalid([] { spline_map(Vector::LinSpaced(3, 0, 1), (Vector(2) << 0.5, INFINITY).finished()); },
                 {"spline_map", "sample_points[1]"});
}

TEST(InvalidInput, Compose) {
  expect_invalid([] { compose(nullptr, exp_map(2)); }, {"compose", "outer map is null"});
  expect_invalid([] { compose(exp_map(2), nullptr); }, {"compose", "inner map is null"});
  expect_invalid(
      [] {
        compose(exp_map(3), region_scatter_map({0, 1}, 2));
      },
      {"compose", "size mismatch", "region_scatter(2 -> 2)", "produces 2", "exp(3)", "takes 3"});
}

TEST(InvalidInput, EmbedBlocks) {
  const Vector base = Vector::Zero(10);
  expect_invalid(
      [&] {
        embed_blocks(base, {{0, exp_map(2)}, {4, nullptr}});
      },
      {"embed_blocks", "block 1", "null"});
  expect_invalid(
      [&] {
        embed_blocks(base, {{-1, exp_map(2)}});
      },
      {"embed_blocks", "block 0", "[-1, 1)", "size 10"});
  expect_invalid(
      [&] {
        embed_blocks(base, {{0, exp_map(2)}, {8, exp_map(3)}});
      },
      {"embed_blocks", "block 1 (exp(3))", "[8, 11)", "outside", "size 10"});
  expect_invalid(
      [&] {
        embed_blocks(base, {{5, exp_map(3)}, {0, identity_map(4)}, {3, exp_map(2)}});
      },
      {"embed_blocks", "blocks 1 [0, 4) and 2 [3, 5) overlap"});
  expect_invalid(
      [&] {
        embed_blocks(base, {{0, exp_map(4)}, {3, exp_map(2)}});
      },
      {"blocks 0 [0, 4) and 1 [3, 5) overlap"});
  // Adjacent blocks and empty blocks are fine.
  EXPECT_NO_THROW(embed_blocks(base, {{0, exp_map(3)}, {3, exp_map(7)}, {2, exp_map(0)}}));
}

}  // namespace
}  // namespace tailor::invalid_input_test
