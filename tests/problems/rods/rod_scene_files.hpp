#pragma once
// The shipped rod scenes (scenes/rods/) as the rod scene tests read them.
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "problems/json_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::testing {

inline std::string rod_scene_path(const std::string& name) {
  return std::string(::tailor::testing::test_data_dir()) + "/../../scenes/rods/" + name;
}

inline nlohmann::json read_json_file(const std::string& path) {
  std::ifstream f(path);
  return parse_json(f);
}

inline nlohmann::json read_rod_scene(const std::string& name) { return read_json_file(rod_scene_path(name)); }

}  // namespace tailor::testing
