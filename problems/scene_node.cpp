#include "problems/scene_node.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "forward/core/format_number.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_error.hpp"

namespace tailor {
namespace {

template <class Words>
std::string join(const Words& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + std::string(w);
  return out;
}

// Path pieces built by appending: GCC 12 reports a spurious -Wrestrict for `"." + std::string`.
std::string member_suffix(const std::string& key) {
  std::string out;
  out.reserve(key.size() + 1);
  out.push_back('.');
  out.append(key);
  return out;
}

std::string index_suffix(std::size_t index) {
  std::string out;
  out.push_back('[');
  out.append(std::to_string(index));
  out.push_back(']');
  return out;
}

}  // namespace

std::string describe_json(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::object:
      return "an object";
    case nlohmann::json::value_t::array:
      return "an array of " + std::to_string(value.size());
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::string: {
      std::string text = dump_json(value);
      if (text.size() > 60) text = text.substr(0, 57) + "...";
      return "a string " + text;
    }
    default:
      return dump_json(value);  // numbers and booleans as written
  }
}

void SceneNode::fail(const std::string& what) const {
  throw SceneError(*source_ + ": " + (path_.empty() ? std::string("(top level)") : path_) + ": " + what);
}

SceneNode SceneNode::child(const nlohmann::json& value, const std::string& suffix) const {
  if (path_.empty() && !suffix.empty() && suffix.front() == '.')
    return SceneNode(value, *source_, suffix.substr(1));
  std::string path = path_;
  path.append(suffix);
  return SceneNode(value, *source_, std::move(path));
}

void SceneNode::expect_keys(std::initializer_list<const char*> allowed) const {
  expect_keys(std::vector<std::string>(allowed.begin(), allowed.end()));
}

void SceneNode::expect_keys(const std::vector<std::string>& allowed) const {
  if (!value_->is_object()) fail("expected an object, got " + describe_json(*value_));
  for (const auto& item : value_->items()) {
    const bool known = std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end();
    if (!known)
      child(item.value(), member_suffix(item.key()))
          .fail("unknown key (allowed here: " + join(allowed) + ")");
  }
}

bool SceneNode::has(const char* key) const { return value_->is_object() && value_->contains(key); }

SceneNode SceneNode::at(const char* key) const {
  if (!value_->is_object()) fail("expected an object, got " + describe_json(*value_));
  const auto it = value_->find(key);
  if (it == value_->end()) fail("missing required key \"" + std::string(key) + "\"");
  return child(*it, member_suffix(key));
}

std::optional<SceneNode> SceneNode::find(const char* key) const {
  if (!value_->is_object()) fail("expected an object, got " + describe_json(*value_));
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return child(*it, member_suffix(key));
}

std::string SceneNode::only_key(std::initializer_list<const char*> choices) const {
  if (!value_->is_object() || value_->size() != 1)
    fail("expected an object with exactly one of the keys " + join(choices) + ", got " +
         describe_json(*value_));
  expect_keys(choices);
  return value_->begin().key();
}

std::vector<SceneNode> SceneNode::items() const {
  if (!value_->is_array()) fail("expected an array, got " + describe_json(*value_));
  std::vector<SceneNode> out;
  for (std::size_t i = 0; i < value_->size(); ++i) out.push_back(child((*value_)[i], index_suffix(i)));
  return out;
}

std::string SceneNode::string() const {
  if (!value_->is_string()) fail("expected a string, got " + describe_json(*value_));
  return value_->get<std::string>();
}

std::string SceneNode::choice(std::initializer_list<const char*> choices) const {
  const std::string s = string();
  if (std::none_of(choices.begin(), choices.end(), [&](const char* c) { return s == c; }))
    fail("expected one of " + join(choices) + ", got \"" + s + "\"");
  return s;
}

std::string SceneNode::choice(const std::vector<std::string>& choices) const {
  const std::string s = string();
  if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    fail("expected one of " + list + ", got \"" + s + "\"");
  }
  return s;
}

bool SceneNode::boolean() const {
  if (!value_->is_boolean()) fail("expected true or false, got " + describe_json(*value_));
  return value_->get<bool>();
}

double SceneNode::number() const {
  if (!value_->is_number()) fail("expected a number, got " + describe_json(*value_));
  const double v = value_->get<double>();
  if (!std::isfinite(v)) fail("expected a finite number, got " + describe_json(*value_));
  return v;
}

double SceneNode::positive() const {
  if (!value_->is_number() || !(value_->get<double>() > 0.0) || !std::isfinite(value_->get<double>()))
    fail("expected a number > 0, got " + describe_json(*value_));
  return value_->get<double>();
}

double SceneNode::non_negative() const {
  if (!value_->is_number() || !(value_->get<double>() >= 0.0) || !std::isfinite(value_->get<double>()))
    fail("expected a number >= 0, got " + describe_json(*value_));
  return value_->get<double>();
}

double SceneNode::open_interval(double lo, double hi) const {
  const bool ok = value_->is_number() && value_->get<double>() > lo && value_->get<double>() < hi;
  if (!ok)
    fail("expected a number in (" + format_number(lo) + ", " + format_number(hi) + "), got " +
         describe_json(*value_));
  return value_->get<double>();
}

int SceneNode::integer(int min) const {
  const bool integral =
      value_->is_number() && std::floor(value_->get<double>()) == value_->get<double>() &&
      std::abs(value_->get<double>()) < static_cast<double>(std::numeric_limits<int>::max());
  if (!integral || value_->get<double>() < min)
    fail("expected an integer >= " + std::to_string(min) + ", got " + describe_json(*value_));
  return static_cast<int>(value_->get<double>());
}

Eigen::VectorXd SceneNode::vector(int size) const {
  const std::string expected =
      size < 0 ? "an array of 2 or 3 numbers" : "an array of " + std::to_string(size) + " numbers";
  const bool size_ok = value_->is_array() && (size < 0 ? (value_->size() == 2 || value_->size() == 3)
                                                       : value_->size() == static_cast<std::size_t>(size));
  if (!size_ok) fail("expected " + expected + ", got " + describe_json(*value_));
  const std::vector<SceneNode> entries = items();
  Eigen::VectorXd v(static_cast<Eigen::Index>(entries.size()));
  for (std::size_t i = 0; i < entries.size(); ++i) v[static_cast<Eigen::Index>(i)] = entries[i].number();
  return v;
}

std::vector<int> SceneNode::integers(int min) const {
  std::vector<int> out;
  for (const SceneNode& item : items()) out.push_back(item.integer(min));
  return out;
}

}  // namespace tailor
