#pragma once
// Torus chain scenes (a `tori` section, keys in docs/scenes.md and docs/tori.md) for
// `tailor simulate`: a hanging chain of interlocked tori (forward/tori/chain.hpp) with implicit
// torus contact or the same tori as triangle meshes with mesh IPC, in static equilibrium (by
// relaxation) or implicit Euler steps. JSON is parsed here into typed structs; the numerical
// code never sees it.
#include <iosfwd>
#include <string>

#include "adjoint/taylor_test.hpp"
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
  // gradcheck.parameters: the design of `tailor gradcheck`, a non-empty subset of "masses",
  // "radii" and "placements" (the fixed links' poses), in that order of z whatever their order
  // here; the rest are held.
  bool gradcheck_masses = true, gradcheck_radii = true, gradcheck_placements = false;
};

class SceneNode;  // problems/scene_node.hpp

// The scene's document. Throws SceneError naming the source and the key path of a bad value
// (unknown keys included).
TorusSceneSpec parse_torus_scene(const SceneNode& root);

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

// `tailor gradcheck` on a static, implicit-contact torus scene (docs/tori.md): the parameters
// z = (m_0 .. m_{n-1}, R_0, r_0, .. R_{n-1}, r_{n-1}, T_f, w_f ..) (the masses in the gravity
// term, the radii in the contact geometry, the placement of each fixed link f in the contact
// term), those selected by the scene's gradcheck.parameters; the objective
// 1/2 sum_free |T_b - T_b^0|^2 over the free links' centres (T_b^0 their start); its gradient by
// the adjoint of the static equilibrium (gravity + the torus barrier, the exact barrier Hessian
// with the distance's implicit-function term, never a projected one) against a Taylor test. The
// equilibrium is first found by relaxation (as in `simulate`), then each free link's w_z is held
// at it (the turn about the vertical through its contact points is a zero mode of the static
// Hessian). Writes DIR/gradcheck.json.
struct TorusGradcheckOptions {
  unsigned seed = 1;
  double initial_step = 1e-5;  // keeps the warm-started equilibrium apart at the new radii
  // Multiplies the adjoint gradient: != 1 only in the test showing that a wrong gradient fails.
  double gradient_scale = 1.0;
};

struct TorusGradcheckRun {
  TaylorTestResult taylor;
  int intersections = 0;        // mesh crossings at the equilibrium (must be 0)
  double min_distance = 0.0;    // at the equilibrium
  int active_pairs = 0;         // pairs within d_hat at the equilibrium (must be > 0)
  bool passed() const { return taylor.passed() && intersections == 0 && active_pairs > 0; }
};

// Throws SceneError for a dynamic or mesh-contact scene, one that does not come to rest, or
// placements asked of a chain without a fixed link.
TorusGradcheckRun gradcheck_torus_scene(const TorusSceneSpec& spec, const std::string& out_dir,
                                        const TorusGradcheckOptions& options, std::ostream* log);

}  // namespace tailor
