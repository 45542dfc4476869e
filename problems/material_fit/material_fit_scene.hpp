#pragma once
// Scenes of type "material_fit" (docs/materials.md): parsed here
// into a MaterialFitSpec; the numerical code never sees JSON.
#include <string>

#include "problems/material_fit/material_fit.hpp"

namespace tailor {

// True when the file is a JSON object with "type": "material_fit" (false for other scenes;
// unreadable or invalid files are left to the regular scene reader to report).
bool is_material_fit_scene(const std::string& path);
// Throws SceneError naming the file and key path.
MaterialFitSpec parse_material_fit_scene(const std::string& json_text, const std::string& source);
MaterialFitSpec read_material_fit_scene(const std::string& path);
// `tailor run` on a material-fit scene: reads, fits, writes into out_dir (out/<name> when empty).
MaterialFitRun run_material_fit_scene(const std::string& path, const std::string& out_dir, std::ostream* log,
                                      std::ostream* progress);

}  // namespace tailor
