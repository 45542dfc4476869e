#pragma once
// Checks of the files every scene kind writes (problems/report_file.hpp).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "problems/json_text.hpp"

namespace tailor::testing {

// The report (report.json, gradcheck.json) starts with the common header of
// problems/report_header.hpp: tailor_version, report_format, threads.
inline void expect_report_header(const std::string& path) {
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  const nlohmann::ordered_json report =
      parse_ordered_json(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
  ASSERT_TRUE(report.is_object() && report.size() >= 3) << path;
  auto key = report.begin();
  EXPECT_EQ(key.key(), "tailor_version") << path;
  EXPECT_EQ((++key).key(), "report_format") << path;
  EXPECT_EQ((++key).key(), "threads") << path;
  EXPECT_TRUE(report["threads"].contains("assembly")) << path;
}

}  // namespace tailor::testing
