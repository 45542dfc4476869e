// The back-ends' and statuses' names, and OptimizerResult::report().
#include "optimizers/optimizer.hpp"

#include <cstdio>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "forward/core/format_number.hpp"
#include "optimizers/backend_registry.hpp"

namespace tailor {

std::string to_string(OptimizerBackend backend) { return std::string(backend.name()); }

OptimizerBackend parse_optimizer_backend(const std::string& name) {
  // The kind views the registry's copy of the name, which lives as long as the program.
  return OptimizerBackend(find_backend(OptimizerBackend(name)).name);
}

std::ostream& operator<<(std::ostream& out, OptimizerBackend backend) { return out << backend.name(); }

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

std::string to_string(CurvatureProducts curvature) {
  switch (curvature) {
    case CurvatureProducts::automatic:
      return "automatic";
    case CurvatureProducts::exact:
      return "exact";
    case CurvatureProducts::gauss_newton:
      return "gauss_newton";
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
  if (!history.empty()) out << format_number(history.front().objective, "%.6e") << " -> ";
  out << format_number(objective, "%.6e") << '\n';
  if (!history.empty()) {
    out << "  gradient norm  : " << format_number(history.back().gradient_norm, "%.3e")
        << " (projected, last iteration)\n";
  }
  out << "  time           : " << format_number(seconds, "%.3f") << " s\n";
  if (!history.empty()) {
    out << "  solves         : " << history.back().forward_solves << " forward, "
        << history.back().adjoint_solves << " adjoint\n";
  }
  if (counters.factorizations > 0 || counters.back_solves > 0 || counters.hessian_vectors > 0) {
    out << "  linear algebra : " << counters.factorizations << " factorizations, " << counters.back_solves
        << " back-solves, " << counters.hessian_vectors << " Hessian-vector products\n";
  }
  return out.str();
}

}  // namespace tailor
