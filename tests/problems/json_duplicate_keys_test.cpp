// Repeated keys in a scene (problems/json_duplicate_keys.hpp): the JSON library keeps the last
// value silently, so the scene reader refuses them, naming the key path and both positions.
#include "problems/json_duplicate_keys.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "problems/cli/run_cli.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"
#include "tests/support/temp_folder.hpp"

namespace tailor::json_duplicate_keys_test {
namespace {

TEST(DuplicateKeys, NamesThePathAndBothPositions) {
  const std::string text =
      "{\"mesh\": {\"box\": {}},\n"
      " \"materials\": [{\"model\": \"linear\"},\n"
      "               {\"model\": \"linear\", \"youngs_modulus\": 1,\n"
      "                \"youngs_modulus\": 2}]}";
  const auto duplicate = find_duplicate_key(text);
  ASSERT_TRUE(duplicate);
  EXPECT_EQ(duplicate->path, "materials[1].youngs_modulus");
  EXPECT_EQ(duplicate->first_line, 3);
  EXPECT_EQ(duplicate->first_column, 36);
  EXPECT_EQ(duplicate->line, 4);
  EXPECT_EQ(duplicate->column, 17);
}

TEST(DuplicateKeys, TheSameKeyInOtherObjectsOrInStringsIsNoDuplicate) {
  // Keys repeat across objects and array elements; strings hold braces, quotes and commas.
  EXPECT_FALSE(find_duplicate_key(R"({"a": {"x": 1}, "b": {"x": 2}, "c": [{"x": 1}, {"x": 2}],
                                      "d": "{\"a\": 1, \"a\": 2}", "e": ["a", "a"]})"));
  EXPECT_FALSE(find_duplicate_key("[]"));
  const auto top = find_duplicate_key(R"({"a": 1, "b": {"a": 1}, "a": 2})");
  ASSERT_TRUE(top);
  EXPECT_EQ(top->path, "a");
  const auto nested = find_duplicate_key(R"({"l": [[{"k": 1}], [{"k": 1, "k": 2}]]})");
  ASSERT_TRUE(nested);
  EXPECT_EQ(nested->path, "l[1][0].k");
}

TEST(DuplicateKeys, TheSceneReaderAndTheCommandLineRefuseThem) {
  try {
    parse_scene_document("{\"name\": \"a\",\n \"name\": \"b\"}", "twice.json");
    ADD_FAILURE() << "a repeated key was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "twice.json: name: the key appears twice (line 1, column 2 and line 2, column 2); JSON would keep "
              "only the last value");
  }
  // Any kind of scene through the command line: a rods scene here, exit 2 with the message.
  const testing::TempFolder folder("duplicate_keys");
  const std::string path = folder / "rod.json";
  std::ofstream(path) << R"({"rods": [{"line": {"from": [0, 0, 0], "to": [1, 0, 0], "vertices": 5},
                             "clamp": ["first"], "clamp": ["last"]}]})";
  std::ostringstream out, err;
  const char* argv[] = {"tailor", "simulate", path.c_str()};
  EXPECT_EQ(run_cli(3, argv, out, err), 2);
  EXPECT_NE(err.str().find("rods[0].clamp: the key appears twice"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace tailor::json_duplicate_keys_test
