#pragma once
// Scenes of type "material_fit" (docs/materials.md): parsed here
// into a MaterialFitSpec; the numerical code never sees JSON.
#include <string>

#include "problems/material_fit/material_fit.hpp"

namespace tailor {

class SceneNode;  // problems/scene_node.hpp

// The scene's document; the name is left empty when the scene gives none. Throws SceneError
// naming the source and key path (unknown keys included).
MaterialFitSpec parse_material_fit_scene(const SceneNode& root);

}  // namespace tailor
