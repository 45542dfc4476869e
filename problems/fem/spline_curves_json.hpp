#pragma once
// The three curves of a principal-stretch spline material (principal_stretch_curves.hpp) as
// JSON, for scenes ("model": "spline") and for the fitted material a material-fit run writes
// (DIR/material.json). One curve is {"lower", "upper", "intervals", "controls"} (uniform cubic
// B-spline, intervals + 3 control values); the three are {"uniaxial", "biaxial", "volumetric"}
// (f, g, h). Internal to problems/: the numerical code sees PrincipalStretchCurves only.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "forward/fem/materials/principal_stretch_curves.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

// {"uniaxial": {...}, "biaxial": {...}, "volumetric": {...}}; throws SceneError naming the key.
PrincipalStretchCurves parse_principal_stretch_curves(const SceneNode& node);

// The curves of a material entry's "curves" key: inline (as above) or {"file": path}, path
// relative to `directory`, a JSON file whose "curves" member holds them (a material-fit run's
// material.json or report.json). Errors inside the file name the file and its key path.
PrincipalStretchCurves parse_curves_or_file(const SceneNode& node, const std::string& directory);

nlohmann::json principal_stretch_curves_json(const PrincipalStretchCurves& curves);

// Writes {"tailor_version", "source", "curves"} to path atomically (report_file.hpp; throws
// std::runtime_error on failure).
void write_spline_material_file(const std::string& path, const PrincipalStretchCurves& curves,
                                const std::string& source);

// The small-strain Lame parameters of the curves (from the tangent at F = I; units of the
// control values, energy per rest volume).
LameParameters small_strain_lame(const PrincipalStretchCurves& curves);

}  // namespace tailor
