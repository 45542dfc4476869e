#pragma once
// `tailor simulate` on a dynamic scene with a "dynamics.reduction" section: the time steps run in
// reduced coordinates u = Phi q (forward/reduction/reduced_dynamics.hpp; docs/reduction.md,
// "Reduced dynamic scenes"). The basis is global (vibration modes, the loads' static response and
// blocks 2..k of their Krylov recurrence), domain-decomposed (Craig-Bampton per METIS domain) or
// overlapping (the global basis blended by principal-direction weights); the reduced energy is the
// exact StVK polynomial (grouped by the columns local to each element) or the projection of the
// full model. Frames are full-space (u = Phi q, v = Phi q'), the report states the basis and r.
#include <ostream>
#include <string>

#include "problems/fem/dynamic_report.hpp"

namespace tailor {

// Runs the reduced steps and writes the frames, result.pvd and report.json like
// simulate_dynamic_scene (which calls it when the scene has dynamics.reduction). Throws
// SceneError for what the reduced path does not take: bdf2, the descent solver, nonzero
// prescribed displacements, an unsupported body, "energy": "polynomial" with a material other
// than StVK.
DynamicRun simulate_reduced_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
