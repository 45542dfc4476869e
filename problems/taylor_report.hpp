#pragma once
// A Taylor test's result as JSON (the fields of gradcheck.json; see docs/scenes.md,
// "tailor gradcheck"): status, message, value, directional_derivative, step, rates and rows.
// Rates that were not measured are written as null.
#include <nlohmann/json.hpp>

#include "adjoint/taylor_test.hpp"

namespace tailor {

nlohmann::ordered_json taylor_json(const TaylorTestResult& result);

}  // namespace tailor
