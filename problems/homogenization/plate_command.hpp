#pragma once
// `tailor homogenize` on a plate-like cell ("cell": {"periodic": [true, true, false]}): the
// bending stiffness D (forward/homogenization/plate_bending.hpp). Writes DIR/report.json
// ("mode": "plate_bending", "bending_stiffness", "directional_bending" with b(d) sampled in the
// x-y plane, "mid_plane", timings) and DIR/bending_stiffness_polar.png.
#include <iosfwd>
#include <string>

#include "problems/homogenization/homogenize_command.hpp"

namespace tailor {

HomogenizeRun homogenize_plate(const CellScene& scene, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
