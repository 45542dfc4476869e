#pragma once
// Scenes built in C++, for `tailor simulate` without a scene file and for tests. They use the
// same Scene structs a JSON file is parsed into.
#include "problems/fem/scene.hpp"

namespace tailor {

// A 10 x 1 x 1 Neo-Hookean beam (30 x 3 x 3 cells of 6 tets), clamped at x = 0 and bent by a
// downward traction of 300 (force per area) on its free end at x = 10; E = 1e6, nu = 0.3. The
// tip deflects by about 0.8: mildly nonlinear; Newton with exact Hessians takes 7 iterations.
// Equivalent to scenes/cantilever.json.
Scene builtin_cantilever();

}  // namespace tailor
