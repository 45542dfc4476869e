#pragma once
// Which file a request for a path below a served folder gets: the studio serves its own page's
// assets and the files of one output folder, nothing else. A path is refused when it is
// absolute, contains a ".." or "." segment, a backslash or a NUL, or resolves (following
// symbolic links) to something outside the folder or to anything but a regular file.
#include <filesystem>
#include <optional>
#include <string>

namespace tailor::studio {

struct ServedPath {
  std::optional<std::filesystem::path> file;  // the canonical path of the file to send
  int status = 200;                           // 200, or 400 (refused) / 404 (no such file)
  std::string reason;                         // why not, when file is empty
};

// `relative`: the request's path below the folder, already percent-decoded ("frames/f_0001.vtu").
ServedPath resolve_served_path(const std::filesystem::path& root, const std::string& relative);

// The Content-Type for a file name's extension ("application/octet-stream" when unknown).
std::string content_type(const std::filesystem::path& file);

}  // namespace tailor::studio
