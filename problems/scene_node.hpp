#pragma once
// SceneNode: a JSON value together with its key path ("materials[1].poisson_ratio") and the
// scene it came from, so that every lookup-and-check in the scene parser is one line and every
// failure is a SceneError that names file and key path. Internal to problems/: nothing outside
// this folder sees JSON.
#include <Eigen/Core>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace tailor {

// The JSON document of a scene's text, or of a scene file. SceneError, naming the source, when
// the file is a folder or cannot be read, for JSON syntax errors (with the byte and nlohmann's
// line and column) and for numbers beyond double precision (with the last key read).
nlohmann::json parse_scene_document(const std::string& json_text, const std::string& source);
nlohmann::json read_scene_document(const std::string& path);

class SceneNode {
 public:
  // The node keeps pointers to `value` and `source`: both must outlive it (temporaries are refused).
  SceneNode(const nlohmann::json& value, const std::string& source, std::string path)
      : value_(&value), source_(&source), path_(std::move(path)) {}
  SceneNode(const nlohmann::json& value, std::string&& source, std::string path) = delete;
  SceneNode(nlohmann::json&& value, const std::string& source, std::string path) = delete;

  const std::string& path() const { return path_; }
  const std::string& source() const { return *source_; }
  const nlohmann::json& json() const { return *value_; }
  // Throws SceneError "<source>: <path>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

  // Objects. `expect_keys` rejects any member not listed (naming the unknown key's path).
  void expect_keys(std::initializer_list<const char*> allowed) const;
  void expect_keys(const std::vector<std::string>& allowed) const;
  bool has(const char* key) const;
  SceneNode at(const char* key) const;  // required member
  std::optional<SceneNode> find(const char* key) const;
  // The single key of an object that must hold exactly one of `choices` (e.g. a selector).
  std::string only_key(std::initializer_list<const char*> choices) const;

  // Arrays.
  std::vector<SceneNode> items() const;

  // Scalars, each with the range it admits; the message says what was expected and got.
  bool is_string() const { return value_->is_string(); }
  std::string string() const;
  std::string choice(std::initializer_list<const char*> choices) const;
  std::string choice(const std::vector<std::string>& choices) const;
  bool boolean() const;
  double number() const;
  double positive() const;                           // > 0
  double non_negative() const;                       // >= 0
  double open_interval(double lo, double hi) const;  // in (lo, hi)
  int integer(int min) const;                        // integral value >= min
  // Fixed-size vector of numbers (size < 0: 2 or 3 entries).
  Eigen::VectorXd vector(int size = -1) const;
  std::vector<int> integers(int min) const;

 private:
  SceneNode child(const nlohmann::json& value, const std::string& suffix) const;
  const nlohmann::json* value_;
  const std::string* source_;
  std::string path_;
};

// Short description of a JSON value for messages: `0.5`, `"abc"`, `an object`, `an array of 2`.
std::string describe_json(const nlohmann::json& value);

}  // namespace tailor
