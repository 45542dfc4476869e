// forward/core/format_number.hpp: the one number-to-text function of the tree.
#include "forward/core/format_number.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace tailor::format_number_test {
namespace {

TEST(FormatNumber, DefaultIsWhatAStreamWrites) {
  for (const double v :
       {0.0, 0.3, -1.5, 1e6, 123456.7, 1e-7, 2.0 / 3.0, std::numeric_limits<double>::infinity()}) {
    std::ostringstream s;
    s << v;
    EXPECT_EQ(format_number(v), s.str()) << v;
  }
}

TEST(FormatNumber, TakesAPrintfConversion) {
  EXPECT_EQ(format_number(0.000123456, "%.3e"), "1.235e-04");
  EXPECT_EQ(format_number(2.5, "%.3f"), "2.500");
  EXPECT_EQ(format_number(0.1, "%.17g"), "0.10000000000000001");
  // Longer than the inline buffer: all of it.
  const std::string huge = format_number(1e300, "%f");
  EXPECT_EQ(huge.size(), 301u + 7u);
  EXPECT_EQ(huge.substr(0, 2), "10");
  EXPECT_EQ(huge.substr(huge.size() - 7), ".000000");
}

}  // namespace
}  // namespace tailor::format_number_test
