#include "problems/taylor_report.hpp"

#include <cmath>

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

}  // namespace

Json taylor_json(const TaylorTestResult& result) {
  Json rows = Json::array();
  for (const TaylorRow& r : result.rows)
    rows.push_back({{"step", r.step},
                    {"value", finite_or_null(r.value)},
                    {"remainder0", finite_or_null(r.remainder0)},
                    {"remainder1", finite_or_null(r.remainder1)},
                    {"rate0", finite_or_null(r.rate0)},
                    {"rate1", finite_or_null(r.rate1)},
                    {"round_off", r.round_off},
                    {"noise", r.noise},
                    {"judged", r.judged}});
  return {{"status", to_string(result.status)},
          {"message", result.message},
          {"value", finite_or_null(result.value)},
          {"directional_derivative", finite_or_null(result.directional_derivative)},
          {"step", result.step},
          {"rate0", finite_or_null(result.rate0)},
          {"rate1", finite_or_null(result.rate1)},
          {"rows", rows}};
}

}  // namespace tailor
