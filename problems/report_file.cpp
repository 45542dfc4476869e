#include "problems/report_file.hpp"

#include <unistd.h>  // fsync, getpid

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "problems/json_text.hpp"
#include "problems/report_header.hpp"

namespace tailor {

void write_text_file_atomically(const std::string& path, const std::string& text) {
  // A name of this process and call: two writers of the same file never share a temporary.
  static std::atomic<unsigned> counter{0};
  const std::string temporary =
      path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter.fetch_add(1));
  std::FILE* file = std::fopen(temporary.c_str(), "wb");
  if (!file) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
  int error = 0;  // the first failure's errno
  const auto check = [&error](bool ok) {
    if (!ok && error == 0) error = errno != 0 ? errno : EIO;
  };
  errno = 0;
  check(std::fwrite(text.data(), 1, text.size(), file) == text.size());
  check(std::fflush(file) == 0);
  check(::fsync(fileno(file)) == 0);
  check(std::fclose(file) == 0);
  if (error == 0) check(std::rename(temporary.c_str(), path.c_str()) == 0);
  if (error == 0) return;
  std::remove(temporary.c_str());
  throw std::runtime_error("cannot write '" + path + "': " + std::strerror(error));
}

void write_report_file(const std::string& path, const nlohmann::ordered_json& report) {
  if (!report.is_object()) throw std::logic_error("a report is a JSON object ('" + path + "')");
  const bool has_header = !report.empty() && report.begin().key() == "tailor_version" &&
                          report.contains("report_format") && report.contains("threads");
  if (has_header) return write_text_file_atomically(path, dump_json(report, 2) + "\n");
  nlohmann::ordered_json out;
  add_report_header(out);
  for (const auto& item : report.items()) out[item.key()] = item.value();
  write_text_file_atomically(path, dump_json(out, 2) + "\n");
}

std::string write_report(const std::string& dir, const nlohmann::ordered_json& report) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create the output folder '" + dir + "': " + error.message());
  const std::string path = (std::filesystem::path(dir) / "report.json").string();
  write_report_file(path, report);
  return path;
}

}  // namespace tailor
