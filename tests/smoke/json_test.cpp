#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace tailor::json_test {
namespace {

TEST(smoke, JsonParseDumpRoundTrip) {
  const auto scene = nlohmann::json::parse(R"({"name": "sheet", "youngs_modulus": 1.5e6,
                                               "fixed": [0, 3, 7], "nested": {"on": true}})");
  EXPECT_EQ(scene.at("name").get<std::string>(), "sheet");
  EXPECT_DOUBLE_EQ(scene.at("youngs_modulus").get<double>(), 1.5e6);
  EXPECT_EQ(scene.at("fixed").get<std::vector<int>>(), (std::vector<int>{0, 3, 7}));
  EXPECT_TRUE(scene.at("nested").at("on").get<bool>());
  EXPECT_EQ(nlohmann::json::parse(scene.dump()), scene);
  EXPECT_EQ(nlohmann::json::parse(scene.dump(2)), scene);
}

}  // namespace
}  // namespace tailor::json_test
