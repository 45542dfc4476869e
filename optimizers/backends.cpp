#include "optimizers/backends.hpp"

#include <IpoptConfig.h>  // IPOPT_VERSION; Debian's 3.11 installs it as coin/IpoptConfig.h
#include <ceres/version.h>

#include <nlopt.hpp>

namespace tailor {

std::vector<BackendInfo> optimizer_backends() {
  int major = 0, minor = 0, bugfix = 0;
  nlopt::version(major, minor, bugfix);
  return {
      {"Ipopt", IPOPT_VERSION},
      {"NLopt", std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(bugfix)},
      {"Ceres", CERES_VERSION_STRING},
  };
}

}  // namespace tailor
