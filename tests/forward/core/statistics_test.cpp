// forward/core/statistics.hpp: the one median of the tree.
#include "forward/core/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tailor::statistics_test {
namespace {

TEST(Median, OddEvenAndEmpty) {
  EXPECT_EQ(median({3.0}), 3.0);
  EXPECT_EQ(median({5.0, 1.0, 3.0}), 3.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);  // the mean of the two middle values
  EXPECT_EQ(median({7.0, 7.0, 1.0, 9.0, 9.0, 9.0}), 8.0);
  EXPECT_TRUE(std::isnan(median({})));
}

}  // namespace
}  // namespace tailor::statistics_test
