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
  bool anisotropic = false;                    // boundary.set
  std::vector<Eigen::Vector2d> limit_strains;  // isotropic: (e_xx, e_yy) of a native principal sweep
  int order = 4;                               // isotropic: of the polar Chebyshev fit
  std::vector<Eigen::Vector3d> oriented_strains;  // anisotropic: (e_xx, e_yy, e_xy) of a sphere sweep
  int degree = 6, max_order = 6;                  // anisotropic: of the spherical-harmonic fit
  interlocking::StrainSetSymmetry symmetry;
  std::vector<Eigen::Vector2d> bending_samples;  // bending_limits: (theta [rad], kappa)
  int bending_order = 0;
  interlocking::DrapeSpec drape;  // with the bending fit when bending_limits is given
};

// The admissible set of the scene's boundary section (the fit).
interlocking::MacroStrainSet macro_strain_set(const InterlockingMacroScene& scene);

// Throws SceneError naming file and key path.
InterlockingMacroScene parse_interlocking_macro_scene(const SceneNode& root);

// The fit, then the drape; writes out_dir/{report.json, sheet.vtu, sphere.vtu, boundary_fit.png}.
// True when Newton converged and the drape is admissible (every margin and gap positive).
bool run_interlocking_macro(const InterlockingMacroScene& scene, const std::string& out_dir,
                            std::ostream* log);

}  // namespace tailor
