#pragma once
// The meshless verbs as values, for callers that want more than the files (the Python module):
// simulate's and run's fields, and the scene with its inverse problem as `tailor gradcheck` and `tailor
// run` build it (problems/meshless/meshless_commands.cpp; the same functions, no second copy).
#include <iosfwd>
#include <memory>
#include <string>

#include "problems/meshless/meshless_commands.hpp"
#include "problems/meshless/meshless_fields.hpp"
#include "problems/meshless/meshless_scene.hpp"

namespace tailor {

struct MeshlessSimulation {
  bool converged = false;
  MeshlessFields fields;  // at the equilibrium, with the scene's parameters
};
// `tailor simulate` (writes report.json, nodes.vtu and samples.vtu into options.out_dir).
MeshlessSimulation simulate_meshless(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);

struct MeshlessRun {
  bool succeeded = false;  // converged, or stopped at the iteration limit (the command line's exit 0)
  std::string status;      // the optimizer's
  Vector design;           // z at the end
  MeshlessFields fields;   // at the equilibrium of z, with its parameters
};
// `tailor run` (writes report.json, nodes.vtu and samples.vtu into options.out_dir).
MeshlessRun run_meshless(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log);

// The scene and its design functional (inverse depends on scene: declared after it, destroyed first).
struct MeshlessDesign {
  std::unique_ptr<MeshlessScene> scene;
  std::unique_ptr<MeshlessInverse> inverse;
};
// SceneError naming the source when the scene has no "inverse" section (`verb` in the message).
MeshlessDesign load_meshless_design(const SceneNode& root, const MeshlessVerbOptions& options, const std::string& verb,
                                    std::ostream* log);

}  // namespace tailor
