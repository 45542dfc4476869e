#pragma once
// The optimization libraries tailor is built against, for logs and bug reports.
#include <string>
#include <vector>

namespace tailor {

struct BackendInfo {
  std::string name;     // "Ipopt", "NLopt", "Ceres"
  std::string version;  // "major.minor.patch"
};

// Ipopt and Ceres report the version of the headers tailor was compiled with (neither has a
// runtime query in the versions Debian 12 ships); NLopt reports the library actually loaded.
std::vector<BackendInfo> optimizer_backends();

}  // namespace tailor
