#pragma once
// The optimizer part that every optimizing verb's report.json shares: one entry per iteration
// with the objective, gradient norm, step, cumulative seconds and solve counts (docs/scenes.md,
// "report.json of tailor run").
#include <nlohmann/json.hpp>

#include "optimizers/optimizer.hpp"

namespace tailor {

nlohmann::ordered_json optimizer_history_json(const OptimizerResult& result);

}  // namespace tailor
