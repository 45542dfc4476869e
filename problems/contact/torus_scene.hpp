#pragma once
// Torus chain scenes (a `tori` section, keys in docs/scenes.md and docs/tori.md) for
// `tailor simulate`: a hanging chain of interlocked tori (forward/tori/chain.hpp) with implicit
// torus contact or the same tori as triangle meshes with mesh IPC, in static equilibrium (by
// relaxation) or implicit Euler steps. JSON is parsed here into typed structs; the numerical
// code never sees it.
#include <iosfwd>
#include <string>

#include "forward/tori/chain_simulation.hpp"

namespace tailor {

struct TorusSceneSpec {
  std::string name, description, source;
  tori::ChainSpec chain;
  tori::ChainSimulationOptions options;
  bool dynamic = false;           // implicit Euler steps of options.time_step; static otherwise
  int steps = 100;                // dynamic
  int output_every = 1;           // .vtu frames every this many steps (dynamic)
  double static_time_step = 1.0;  // static: the relaxation's step [time]
  double static_tolerance = 0.0;  // static: rest when no DOF moves more than this; 0: 1e-10 R
  int max_static_steps = 200;
};

// Throws SceneError naming the file and the key path of a bad value.
TorusSceneSpec parse_torus_scene(const std::string& json_text, const std::string& source);

struct TorusSimulateRun {
  bool converged = false;  // every step converged (static: and the chain came to rest)
  int steps = 0;
  int intersections = 0;   // mesh edge-face crossings over all accepted steps (must be 0)
  double min_distance = 0.0;
  bool completed() const { return converged && intersections == 0; }
};

// Runs the scene; writes DIR/report.json and DIR/<link>_<frame>.vtu (every torus's mesh per
// frame; static: the start and the equilibrium). Progress to `log` when given.
TorusSimulateRun simulate_torus_scene(const TorusSceneSpec& spec, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
