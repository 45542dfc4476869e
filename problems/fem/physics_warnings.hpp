#pragma once
// Warnings where a FEM scene's physics is likely misused: the run goes on (the input is valid),
// but its answer is probably not what the user wants. Each names the scene file and key path and
// says what to do. The command line prints them ("warning: ...") before the solve; the dynamic
// report lists them under "warnings".
#include <string>
#include <vector>

#include "problems/fem/scene.hpp"

namespace tailor {

// Poisson's ratio at or above this on linear simplices: volumetric locking.
inline constexpr double kLockingPoissonRatio = 0.49;

// One warning per material (not a spline one) with poisson_ratio >= kLockingPoissonRatio: linear
// tets and triangles lock in near incompressibility (the displacements come out too small, by a
// factor that grows like 1 / (1 - 2 nu) under bending).
std::vector<std::string> locking_warnings(const Scene& scene);

// Newmark's average acceleration rule neither damps nor resolves a vibration whose period T is
// short against the step h: each step turns it by 2 atan(pi h / T), nearly pi when h >> T, so its
// energy alternates from step to step (a period-2 oscillation) while the run reports success.
// A warning when the scene's scheme is newmark and h is above half the body's longest natural
// period T1 at rest (the lowest elastic mode, from modal_analysis): every vibration of the body
// is then unresolved. Empty when the scheme is not newmark, h is small enough, or the modes cannot
// be computed (no density, a free body's modes failing): the warning is advice, never an error.
std::vector<std::string> time_step_warnings(const Scene& scene);

}  // namespace tailor
