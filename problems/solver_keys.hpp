#pragma once
// Scene keys of the Newton solver that several scene kinds share (docs/scenes.md, "solver").
// Internal to problems/: failures are SceneErrors naming file and key path.
#include "forward/solve/newton.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

// "reuse_factorization": true (FactorReuse::on), false (off) or "auto" (automatic).
inline FactorReuse parse_factor_reuse(const SceneNode& node) {
  if (node.json().is_boolean()) return node.boolean() ? FactorReuse::on : FactorReuse::off;
  if (node.is_string() && node.json().get<std::string>() == "auto") return FactorReuse::automatic;
  node.fail("expected true, false or \"auto\", got " + describe_json(node.json()));
}

}  // namespace tailor
