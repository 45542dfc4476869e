#pragma once
// `tailor homogenize cell.json [--out DIR]`: linear homogenization of a periodic-cell scene.
// Writes DIR/report.json (C^H, S, engineering constants, E(d) and nu(d) sampled, timings),
// DIR/youngs_modulus_polar.png (E(d) as a polar curve; 3D: the xy, yz and zx sections),
// DIR/poisson_ratio.png (nu(d, n) against the angle of d, n = d turned by +90 degrees in the
// same plane) and DIR/load_case_<ij>.vtu per unit macro strain (displacement, fluctuation,
// per-element stress, phase and Young's modulus). Format in docs/homogenization.md.
#include <iosfwd>
#include <string>

#include "forward/homogenization/linear_homogenization.hpp"
#include "problems/homogenization/cell_scene.hpp"

namespace tailor {

struct DirectionalSamples {
  std::string plane;          // "xy", "yz", "zx"
  std::vector<double> angle;  // radians from the plane's first axis
  std::vector<double> youngs_modulus, poisson_ratio;
};

// E(d) and nu(d, n) at `count` angles over 360 degrees in each coordinate plane (one in 2D).
std::vector<DirectionalSamples> sample_directions(const Matrix& compliance, int count);

struct HomogenizeRun {
  LinearHomogenization result;  // for a plate-like cell: result.stiffness is the bending stiffness D
  Matrix compliance;
};

// Homogenizes and writes the outputs into out_dir (created); progress to `log` when set. A
// plate-like cell ("periodic": [true, true, false]) gets its bending stiffness instead
// (plate_command.hpp), a rod-network cell its membrane stiffness (rod_network_command.hpp).
// Throws std::runtime_error naming the file when an output cannot be written.
HomogenizeRun homogenize_scene(const CellScene& scene, const std::string& out_dir, std::ostream* log);

// The cell's per-load-case fields as .vtu files, "<out_dir>/<prefix><ij>.vtu".
void write_cell_fields(const std::string& out_dir, const std::string& prefix, LinearCell& cell,
                       const LinearHomogenization& result, const Vector& youngs_modulus,
                       const std::vector<int>& element_phase);

}  // namespace tailor
