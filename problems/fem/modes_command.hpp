#pragma once
// `tailor modes`: modal analysis of a static scene at rest (forward/reduction/modal_analysis.hpp)
// with the consistent mass matrix of the materials' densities. Writes DIR/report.json
// (frequencies in Hz, eigenvalues, rigid-body modes set apart) and DIR/modes.vtu (one point
// field per mode shape).
#include <iosfwd>
#include <string>

#include "forward/reduction/modal_analysis.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

struct ModesRun {
  ModalAnalysis modes;
  double total_mass = 0.0;
  double seconds = 0.0;     // setup + eigen solve
  std::string report_path;  // out_dir/report.json
  std::string modes_path;   // out_dir/modes.vtu
};

// count: elastic modes wanted (>= 1). Throws SceneError when a material has no positive
// density (the mass matrix would be singular) or count is out of range for the mesh, and
// std::runtime_error when the eigen solve fails or the outputs cannot be written.
ModesRun modes_scene(const Scene& scene, int count, const std::string& out_dir, std::ostream* log = nullptr);

}  // namespace tailor
