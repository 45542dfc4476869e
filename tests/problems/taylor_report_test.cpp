// problems/taylor_report.hpp: a Taylor test that failed on an infinite value still gives a
// gradcheck.json that parses (non-finite numbers as null, control characters escaped).
#include "problems/taylor_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "problems/json_text.hpp"

namespace tailor::taylor_report_test {
namespace {

TEST(TaylorReport, NonFiniteValuesAreNullAndTheTextStaysValidJson) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  TaylorTestResult result;
  result.status = TaylorStatus::evaluation_failed;
  result.message = "J(z + h dz) = inf at h = 1e-2\n\t(line search\x01)";
  result.value = inf;
  result.directional_derivative = -inf;
  result.rate0 = std::nan("");
  result.rate1 = 2.0;
  result.rows.push_back({1e-2, inf, inf, std::nan(""), std::nan(""), std::nan(""), false, inf, true});

  const std::string text = dump_json(taylor_json(result), 2);
  const nlohmann::json parsed = parse_json(text);  // throws on invalid JSON
  EXPECT_EQ(parsed["status"], "evaluation_failed");
  EXPECT_EQ(parsed["message"], result.message);
  EXPECT_NE(text.find("\\u0001"), std::string::npos) << text;
  EXPECT_TRUE(parsed["value"].is_null());
  EXPECT_TRUE(parsed["directional_derivative"].is_null());
  EXPECT_TRUE(parsed["rate0"].is_null());
  EXPECT_EQ(parsed["rate1"], 2.0);
  ASSERT_EQ(parsed["rows"].size(), 1u);
  EXPECT_EQ(parsed["rows"][0]["step"], 1e-2);
  EXPECT_TRUE(parsed["rows"][0]["remainder0"].is_null());
  EXPECT_TRUE(parsed["rows"][0]["noise"].is_null());
  EXPECT_EQ(text.find(": inf"), std::string::npos) << text;  // "inf" only inside the message
  EXPECT_EQ(text.find(": -inf"), std::string::npos) << text;
  EXPECT_EQ(text.find("nan"), std::string::npos);
}

}  // namespace
}  // namespace tailor::taylor_report_test
