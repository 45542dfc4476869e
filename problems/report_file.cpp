#include "problems/report_file.hpp"

#include <filesystem>
#include <stdexcept>

#include "problems/json_text.hpp"
#include "problems/report_header.hpp"

namespace tailor {

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
