#pragma once
// Writing a run's reports so that a reader sees the old file or the new one, never a part
// (forward/core/atomic_file.hpp). Every kind's report.json (and gradcheck.json) is written by
// write_report, which also puts the common header (report_header.hpp) first.
#include <nlohmann/json.hpp>
#include <string>

#include "forward/core/atomic_file.hpp"  // write_text_file_atomically

namespace tailor {

// `report` (a JSON object) written atomically to `path`, indented by 2, starting with the fields
// of add_report_header (tailor_version, report_format, threads; the report's own values of
// those fields are kept). Throws std::runtime_error like write_text_file_atomically.
void write_report_file(const std::string& path, const nlohmann::ordered_json& report);

// `dir`/report.json by write_report_file; `dir` is created when missing. Returns the path.
std::string write_report(const std::string& dir, const nlohmann::ordered_json& report);

}  // namespace tailor
