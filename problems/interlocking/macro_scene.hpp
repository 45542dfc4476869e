#pragma once
// Scenes of the macro-scale interlocking sheet (docs/interlocking.md, "Macro-scale model"): an
// "interlocking_macro" section with the measured boundary, the sheet's material and a drape over a
// sphere.
//   tailor simulate scene.json   the fit and the drape: report.json, sheet.vtu, sphere.vtu,
//                                boundary_fit.png
#include <iosfwd>
#include <string>
#include <vector>

#include "forward/interlocking/macro_drape.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

struct InterlockingMacroScene {
  std::string name;
  std::vector<Eigen::Vector2d> limit_strains;  // (e_xx, e_yy) of a native principal sweep
  int order = 4;                               // of the polar Chebyshev fit
  interlocking::DrapeSpec drape;
};

// Throws SceneError naming file and key path.
InterlockingMacroScene parse_interlocking_macro_scene(const SceneNode& root);

// The fit, then the drape; writes out_dir/{report.json, sheet.vtu, sphere.vtu, boundary_fit.png}.
// True when Newton converged and the drape is admissible (every margin and gap positive).
bool run_interlocking_macro(const InterlockingMacroScene& scene, const std::string& out_dir,
                            std::ostream* log);

}  // namespace tailor
