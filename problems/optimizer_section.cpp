#include "problems/optimizer_section.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "problems/scene_node.hpp"

namespace tailor {

OptimizerOptions parse_optimizer_section(const SceneNode& node, OptimizerOptions o,
                                         const OptimizerSectionSupport& support) {
  std::vector<std::string> keys = {
      "backend",        "max_iterations", "gradient_tolerance", "objective_tolerance",
      "step_tolerance", "time_limit"};
  const std::string kind = support.kind;
  if (support.exact_hessian)
    keys.emplace_back("exact_hessian");
  else if (const auto v = node.find("exact_hessian"))
    v->fail(kind +
            " cannot use exact Hessians (its optimization has no Hessian-vector products or has "
            "constraints)");
  if (support.checkpoint_every)
    keys.emplace_back("checkpoint_every");
  else if (const auto v = node.find("checkpoint_every"))
    v->fail(kind + " writes no optimizer checkpoints");
  node.expect_keys(keys);

  if (const auto b = node.find("backend")) {
    try {
      o.backend = parse_optimizer_backend(b->string());
    } catch (const std::invalid_argument& e) {
      b->fail(e.what());
    }
  }
  if (const auto v = node.find("max_iterations")) o.max_iterations = v->integer(1);
  if (const auto v = node.find("gradient_tolerance")) o.gradient_tolerance = v->non_negative();
  if (const auto v = node.find("objective_tolerance")) o.objective_tolerance = v->non_negative();
  if (const auto v = node.find("step_tolerance")) o.step_tolerance = v->non_negative();
  if (const auto v = node.find("time_limit")) o.time_limit_seconds = v->non_negative();
  if (const auto v = node.find("checkpoint_every")) o.checkpoint_every = v->integer(0);
  const BackendCapabilities& has = find_backend(o.backend).capabilities;
  if (const auto v = node.find("exact_hessian")) {
    o.exact_hessian = v->boolean();
    if (o.exact_hessian && !has.exact_hessian)
      v->fail("only the " + backends_with(&BackendCapabilities::exact_hessian) +
              " back-end uses exact Hessians (the back-end is " + to_string(o.backend) + ")");
  }
  const struct {
    bool BackendCapabilities::*capability;
    const char* what;
  } needs[] = {{&BackendCapabilities::bounds, "bounds"},
               {&BackendCapabilities::inequality_constraints, "inequality constraints"},
               {&BackendCapabilities::equality_constraints, "equality constraints"}};
  for (const auto& need : needs)
    if (support.needs.*need.capability && !(has.*need.capability)) {
      const std::string what = to_string(o.backend) + " does not support " + need.what + ", which " + kind +
                               " needs (choose one of " + backends_with(need.capability) + ")";
      if (const auto b = node.find("backend")) b->fail(what);
      node.fail(what);
    }
  return o;
}

}  // namespace tailor
