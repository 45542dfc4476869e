#pragma once
// `tailor homogenize` on a rod-network cell (a periodic-cell scene with "rod_network"):
// DIR/report.json (membrane stiffness C [force/length], compliance, engineering constants, E(d)
// and nu(d) sampled, with "depth" also the moduli C / depth, the network's size and timings),
// DIR/youngs_modulus_polar.png, DIR/poisson_ratio.png and DIR/load_case_<ij>.vtu (the rods
// under each unit macro strain, write_rods_vtu's fields). Format in docs/homogenization.md.
#include <iosfwd>
#include <string>

#include "problems/homogenization/homogenize_command.hpp"

namespace tailor {

// result.stiffness is the membrane stiffness C. Throws std::runtime_error for a mechanism (a
// singular cell) and when an output cannot be written.
HomogenizeRun homogenize_rod_network(const CellScene& scene, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
