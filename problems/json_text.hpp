#pragma once
// JSON text in and out, compiled once (problems/json_text.cpp). nlohmann's parser and serializer
// are templates: a translation unit that calls json::parse or dump() itself compiles them again,
// about 1.5 s each at -O2 (docs/testing.md, "Build time"). Every reader and writer of tailor,
// its tests and benches go through these instead.
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

namespace tailor {

// nlohmann::json::parse(text) / parse(in): throws nlohmann::json::parse_error.
nlohmann::json parse_json(const std::string& text);
nlohmann::json parse_json(std::istream& in);
nlohmann::json parse_json(std::istream&& in);
// Without exceptions: a value whose is_discarded() is true when the text is not JSON.
nlohmann::json parse_json_or_discarded(const std::string& text);
nlohmann::json parse_json_or_discarded(std::istream& in);
nlohmann::ordered_json parse_ordered_json(const std::string& text);

// value.dump(indent); with replace_invalid_utf8, bytes that are not UTF-8 become U+FFFD instead
// of throwing nlohmann::json::type_error.
std::string dump_json(const nlohmann::json& value, int indent = -1, bool replace_invalid_utf8 = false);
std::string dump_json(const nlohmann::ordered_json& value, int indent = -1,
                      bool replace_invalid_utf8 = false);

}  // namespace tailor

namespace nlohmann {
// GoogleTest prints a json that an assertion names through this, not through operator<<, so a
// test file does not compile the serializer again.
void PrintTo(const json& value, std::ostream* os);
void PrintTo(const ordered_json& value, std::ostream* os);
}  // namespace nlohmann
