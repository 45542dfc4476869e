#include "problems/optimizer_report.hpp"

namespace tailor {

nlohmann::ordered_json optimizer_history_json(const OptimizerResult& result) {
  nlohmann::ordered_json history = nlohmann::ordered_json::array();
  for (const OptimizerIteration& it : result.history)
    history.push_back({{"iteration", it.iteration},
                       {"objective", it.objective},
                       {"gradient_norm", it.gradient_norm},
                       {"step", it.step_norm},
                       {"seconds", it.seconds},
                       {"forward_solves", it.forward_solves},
                       {"adjoint_solves", it.adjoint_solves}});
  return history;
}

}  // namespace tailor
