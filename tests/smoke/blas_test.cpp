#include <gtest/gtest.h>

#include <cstdio>

#include "forward/solve/blas_info.hpp"

namespace tailor::blas_test {
namespace {

// This binary links Ceres, whose Debian target hard-links ATLAS. If ATLAS's libf77blas got
// into the process ahead of the system BLAS, dgemm_ -- and with it all of CHOLMOD's dense
// work -- would run on ATLAS, about 2.5x slower. tailorDependencies.cmake strips those
// libraries; this test catches any regression.
TEST(smoke, BlasDgemmComesFromOpenBlas) {
  const std::string path = blas_library_path();
  std::printf("dgemm_ provided by: %s\n", path.c_str());
  EXPECT_NE(path.find("openblas"), std::string::npos) << path;
}

}  // namespace
}  // namespace tailor::blas_test
