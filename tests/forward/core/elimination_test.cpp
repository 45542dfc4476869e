#include "forward/core/elimination.hpp"

#include <gtest/gtest.h>

namespace tailor::elimination_test {
namespace {

TEST(Elimination, DirichletSelectsFreeDofsInOrder) {
  Vector values = Vector::LinSpaced(5, 0.0, 4.0);
  const Elimination e = Elimination::dirichlet({1, 3}, values);
  ASSERT_EQ(e.num_free(), 3);
  EXPECT_TRUE(e.is_selection());
  Vector y(3);
  y << 10, 20, 30;
  const Vector x = e.expand(y);
  EXPECT_DOUBLE_EQ(x[0], 10);
  EXPECT_DOUBLE_EQ(x[1], 1);
  EXPECT_DOUBLE_EQ(x[2], 20);
  EXPECT_DOUBLE_EQ(x[3], 3);
  EXPECT_DOUBLE_EQ(x[4], 30);
  EXPECT_TRUE(e.restrict_state(x).isApprox(y));
  EXPECT_THROW(Elimination::dirichlet({7}, values), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::elimination_test
