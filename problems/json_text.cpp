#include "problems/json_text.hpp"

#include <istream>
#include <ostream>

namespace tailor {

nlohmann::json parse_json(const std::string& text) { return nlohmann::json::parse(text); }

nlohmann::json parse_json(std::istream& in) { return nlohmann::json::parse(in); }

nlohmann::json parse_json(std::istream&& in) { return nlohmann::json::parse(in); }

nlohmann::json parse_json_or_discarded(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, false);
}

nlohmann::json parse_json_or_discarded(std::istream& in) { return nlohmann::json::parse(in, nullptr, false); }

nlohmann::ordered_json parse_ordered_json(const std::string& text) {
  return nlohmann::ordered_json::parse(text);
}

namespace {
template <class Json>
std::string dump(const Json& value, int indent, bool replace_invalid_utf8) {
  return value.dump(indent, ' ', false,
                    replace_invalid_utf8 ? Json::error_handler_t::replace : Json::error_handler_t::strict);
}
}  // namespace

std::string dump_json(const nlohmann::json& value, int indent, bool replace_invalid_utf8) {
  return dump(value, indent, replace_invalid_utf8);
}

std::string dump_json(const nlohmann::ordered_json& value, int indent, bool replace_invalid_utf8) {
  return dump(value, indent, replace_invalid_utf8);
}

}  // namespace tailor

namespace nlohmann {
void PrintTo(const json& value, std::ostream* os) { *os << tailor::dump_json(value, -1, true); }
void PrintTo(const ordered_json& value, std::ostream* os) { *os << tailor::dump_json(value, -1, true); }
}  // namespace nlohmann
