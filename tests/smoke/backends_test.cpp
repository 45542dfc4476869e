#include "optimizers/backends.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace tailor::backends_test {
namespace {

TEST(smoke, OptimizerBackendsReportIpoptNloptCeres) {
  const std::vector<BackendInfo> backends = optimizer_backends();
  ASSERT_EQ(backends.size(), 3u);
  EXPECT_EQ(backends[0].name, "Ipopt");
  EXPECT_EQ(backends[1].name, "NLopt");
  EXPECT_EQ(backends[2].name, "Ceres");
  for (const BackendInfo& backend : backends) {
    std::printf("%s %s\n", backend.name.c_str(), backend.version.c_str());
    // "major.minor.patch"
    EXPECT_EQ(std::count(backend.version.begin(), backend.version.end(), '.'), 2) << backend.version;
  }
}

}  // namespace
}  // namespace tailor::backends_test
