#include "problems/studio/served_path.hpp"

#include <map>
#include <system_error>

namespace tailor::studio {
namespace fs = std::filesystem;

ServedPath resolve_served_path(const fs::path& root, const std::string& relative) {
  const auto refuse = [](int status, std::string reason) { return ServedPath{std::nullopt, status, std::move(reason)}; };
  if (relative.empty()) return refuse(404, "no file named");
  if (relative.find('\0') != std::string::npos) return refuse(400, "a NUL in the path");
  if (relative.find('\\') != std::string::npos) return refuse(400, "a backslash in the path");
  if (relative.front() == '/') return refuse(400, "an absolute path");
  // Segment by segment: "..", "." and empty segments ("a//b") are refused, not normalized.
  std::size_t begin = 0;
  while (begin <= relative.size()) {
    const std::size_t end = std::min(relative.find('/', begin), relative.size());
    const std::string segment = relative.substr(begin, end - begin);
    if (segment == ".." || segment == "." || segment.empty()) return refuse(400, "a '" + segment + "' segment");
    begin = end + 1;
  }
  std::error_code error;
  const fs::path base = fs::canonical(root, error);
  if (error) return refuse(404, "the served folder does not exist");
  const fs::path file = fs::canonical(base / relative, error);  // follows every symbolic link
  if (error) return refuse(404, "no such file");
  // The resolved file must lie below the folder, component by component.
  auto b = base.begin();
  auto f = file.begin();
  for (; b != base.end(); ++b, ++f)
    if (f == file.end() || *f != *b) return refuse(400, "a link out of the served folder");
  if (f == file.end()) return refuse(400, "the folder itself");
  if (!fs::is_regular_file(file, error)) return refuse(404, "not a regular file");
  return ServedPath{file, 200, ""};
}

std::string content_type(const fs::path& file) {
  static const std::map<std::string, std::string> types = {
      {".html", "text/html; charset=utf-8"},   {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"}, {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},             {".png", "image/png"},
      {".svg", "image/svg+xml"},                 {".vtu", "application/xml"},
      {".pvd", "application/xml"},               {".txt", "text/plain; charset=utf-8"},
      {".csv", "text/csv; charset=utf-8"}};
  const auto found = types.find(file.extension().string());
  return found == types.end() ? "application/octet-stream" : found->second;
}

}  // namespace tailor::studio
