#include "problems/report_header.hpp"

#include "forward/solve/threads.hpp"
#include "tailor_version.hpp"

namespace tailor {

void add_report_header(nlohmann::ordered_json& report) {
  report["tailor_version"] = version_string;
  report["report_format"] = kReportFormatVersion;
  const ThreadReport threads = current_threads();
  report["threads"] = {{"assembly", threads.assembly},
                       {"blas", threads.blas},
                       {"factorization", threads.factorization},
                       {"blas_library", threads.blas_library}};
}

}  // namespace tailor
