#pragma once
// The "optimizer" section of every scene kind that optimizes (docs/scenes.md, "The optimizer
// section"), parsed by one function so that a section means the same options in every kind:
//   backend             a registered back-end (optimizers/backend_registry.hpp)
//   max_iterations      integer >= 1
//   gradient_tolerance, objective_tolerance, step_tolerance, time_limit   numbers >= 0
//   exact_hessian       true / false; true needs a back-end that uses exact Hessians
//   checkpoint_every    integer >= 0
// Keys not given keep the kind's defaults. A kind that cannot honour exact_hessian or
// checkpoint_every refuses the key, saying so; any other key is unknown.
#include "optimizers/backend_registry.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

class SceneNode;  // problems/scene_node.hpp

// What a kind does with the section beyond the keys every kind honours.
struct OptimizerSectionSupport {
  const char* kind = "this scene";  // in messages, e.g. "a rod scene"
  // The kind's functional has Hessian-vector products and no constraints (exact_hessian).
  bool exact_hessian = false;
  // The kind writes checkpoints (checkpoint_every; `tailor run --resume`).
  bool checkpoint_every = false;
  // What the kind's problem needs of the back-end (bounds, constraints): a back-end without it
  // is refused at "backend", naming the back-ends that have it.
  BackendCapabilities needs;
};

// Throws SceneError naming the key path for bad values, unknown keys and keys `support` leaves
// out.
OptimizerOptions parse_optimizer_section(const SceneNode& node, OptimizerOptions defaults,
                                         const OptimizerSectionSupport& support);

}  // namespace tailor
