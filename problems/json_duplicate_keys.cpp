#include "problems/json_duplicate_keys.hpp"

#include <map>
#include <utility>
#include <vector>

namespace tailor {
namespace {

// One open object or array: its key path, and for objects the keys seen (with their positions)
// and the key whose value comes next; for arrays the index of the current element.
struct Frame {
  bool object = false;
  std::string path;
  std::map<std::string, std::pair<int, int>> keys;
  std::string key;
  bool expect_key = false;
  int index = 0;
};

std::string member_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

}  // namespace

std::optional<DuplicateKey> find_duplicate_key(const std::string& text) {
  std::vector<Frame> open;
  int line = 1, column = 1;
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '"') {
      const int start_line = line, start_column = column;
      std::size_t j = i + 1;
      while (j < n && text[j] != '"') j += text[j] == '\\' ? 2 : 1;
      // The raw text between the quotes identifies the key (escapes are rare in scene keys).
      const std::string raw = text.substr(i + 1, j - i - 1);
      column += static_cast<int>(j - i);  // strings hold no raw newline in valid JSON
      i = j;
      if (!open.empty() && open.back().object && open.back().expect_key) {
        Frame& frame = open.back();
        const auto [it, fresh] = frame.keys.emplace(raw, std::make_pair(start_line, start_column));
        if (!fresh)
          return DuplicateKey{member_path(frame.path, raw), it->second.first, it->second.second, start_line,
                              start_column};
        frame.key = raw;
        frame.expect_key = false;
      }
    } else if (c == '{' || c == '[') {
      Frame frame;
      frame.object = c == '{';
      frame.expect_key = frame.object;
      if (!open.empty())
        frame.path = open.back().object ? member_path(open.back().path, open.back().key)
                                        : open.back().path + "[" + std::to_string(open.back().index) + "]";
      open.push_back(std::move(frame));
    } else if (c == '}' || c == ']') {
      if (!open.empty()) open.pop_back();
    } else if (c == ',' && !open.empty()) {
      if (open.back().object)
        open.back().expect_key = true;
      else
        ++open.back().index;
    }
    if (c == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::nullopt;
}

}  // namespace tailor
