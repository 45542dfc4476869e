#pragma once
// `tailor studio SCENE_OR_OUT_DIR [--port N]` (docs/studio.md): a handle scene with
// inverse.design.reduction opens the interactive design; any other scene opens the viewer of its
// output folder (out/<scene stem>, or --out DIR); a folder opens the viewer of that folder.
// Registered by bin/tailor's main() when tailor is built with the studio (TAILOR_HAVE_STUDIO).
#include <filesystem>

#include "problems/scene_kinds.hpp"

namespace tailor::studio {

Verb studio_verb();

// Where the page's built assets are: $TAILOR_STUDIO_ASSETS, else share/tailor/studio next to the
// folder of the running program (the build tree's and the installed layout alike). Empty when
// neither holds an index.html.
std::filesystem::path find_studio_assets();

}  // namespace tailor::studio
