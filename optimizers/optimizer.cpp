// The back-ends' and statuses' names, and OptimizerResult::report().
#include "optimizers/optimizer.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace tailor {

namespace {

struct BackendName {
  OptimizerBackend backend;
  const char* name;
};
constexpr BackendName kBackendNames[] = {
    {OptimizerBackend::ipopt, "ipopt"},
    {OptimizerBackend::nlopt_lbfgs, "nlopt_lbfgs"},
    {OptimizerBackend::nlopt_mma, "nlopt_mma"},
    {OptimizerBackend::nlopt_slsqp, "nlopt_slsqp"},
    {OptimizerBackend::ceres_lbfgs, "ceres_lbfgs"},
    {OptimizerBackend::ceres_least_squares, "ceres_least_squares"},
    {OptimizerBackend::gradient_descent, "gradient_descent"},
};

std::string format_number(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace

std::string to_string(OptimizerBackend backend) {
  for (const auto& entry : kBackendNames)
    if (entry.backend == backend) return entry.name;
  return "unknown";
}

OptimizerBackend parse_optimizer_backend(const std::string& name) {
  std::string known;
  for (const auto& entry : kBackendNames) {
    if (name == entry.name) return entry.backend;
    known += known.empty() ? "" : ", ";
    known += entry.name;
  }
  throw std::invalid_argument("unknown optimizer back-end '" + name + "' (known: " + known + ")");
}

std::string to_string(OptimizerStatus status) {
  switch (status) {
    case OptimizerStatus::converged:
      return "converged";
    case OptimizerStatus::max_iterations:
      return "max_iterations";
    case OptimizerStatus::time_limit:
      return "time_limit";
    case OptimizerStatus::interrupted:
      return "interrupted";
    case OptimizerStatus::failed:
      return "failed";
  }
  return "unknown";
}

std::string OptimizerResult::report() const {
  std::ostringstream out;
  out << "Optimizer report\n";
  // The message starts with the back-end's name ("nlopt_lbfgs: ..."), see minimize().
  const auto colon = message.find(": ");
  if (colon != std::string::npos) {
    try {
      out << "  backend        : " << to_string(parse_optimizer_backend(message.substr(0, colon))) << '\n';
    } catch (const std::invalid_argument&) {
    }
  }
  out << "  status         : " << to_string(status) << '\n';
  out << "  message        : " << message << '\n';
  if (resumed_from) out << "  resumed        : from the checkpoint at iteration " << *resumed_from << '\n';
  const int iterations = history.empty() ? 0 : history.back().iteration;
  out << "  iterations     : " << iterations << '\n';
  out << "  evaluations    : " << evaluations << '\n';
  if (failed_evaluations > 0)
    out << "  failed points  : " << failed_evaluations << " (forward solve failed; the step was shortened)\n";
  out << "  objective      : ";
  if (!history.empty()) out << format_number("%.6e", history.front().objective) << " -> ";
  out << format_number("%.6e", objective) << '\n';
  if (!history.empty()) {
    out << "  gradient norm  : " << format_number("%.3e", history.back().gradient_norm)
        << " (projected, last iteration)\n";
  }
  out << "  time           : " << format_number("%.3f", seconds) << " s\n";
  if (!history.empty()) {
    out << "  solves         : " << history.back().forward_solves << " forward, "
        << history.back().adjoint_solves << " adjoint\n";
  }
  return out.str();
}

}  // namespace tailor
