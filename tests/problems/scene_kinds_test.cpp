// Every scene kind through the command line's handlers (problems/scene_kinds.hpp): each handler
// takes the parsed document, from a file or from memory; a misspelled key in any kind is refused
// by every verb of the kind, naming the scene and the key path.
#include "problems/scene_kinds.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "../support/temp_folder.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"

namespace tailor::scene_kinds_test {
namespace {

using testing::TempFolder;

// The error a verb's handler throws for the scene, or "" when it throws none.
std::string handler_error(const SceneKind& kind, const KindVerb& verb, const SceneFile& file,
                          const std::string& out_dir) {
  VerbArguments args;
  args.verb = verb.verb;
  args.out_dir = out_dir;
  args.quiet = true;
  std::ostringstream out;
  try {
    verb.handler(file, args, out);
  } catch (const SceneError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << kind.name << " " << verb.verb << ": not a SceneError: " << e.what();
  }
  return "";
}

TEST(SceneKinds, AMisspelledKeyIsRefusedByEveryVerbNamingTheSceneAndTheKeyPath) {
  const TempFolder folder("scene_kinds_misspelled");
  const nlohmann::json damping = parse_json(R"({"name": "plate", "damping_design": {
      "plate": {"cells": [8, 2, 1]}, "examples": [{"mode": 0, "scale": 0.1}], "steps": 10}})");
  const struct {
    std::string scene;  // under scenes/; empty: `damping`
    std::string kind;
    std::string object;  // JSON pointer of the object that gets the key
    std::string key, path;
  } cases[] = {
      {"cantilever.json", "static", "/materials/0", "youngs_modulu", "materials[0].youngs_modulu"},
      {"swinging_beam.json", "dynamic", "/dynamics", "time_stp", "dynamics.time_stp"},
      {"contact/box_on_ground.json", "rigid_bodies", "/rigid_bodies/0", "densty", "rigid_bodies[0].densty"},
      {"contact/torus_chain.json", "tori", "/tori", "cout", "tori.cout"},
      {"rods/rod_stiffness_design.json", "rods", "/inverse/optimizer", "max_iteration",
       "inverse.optimizer.max_iteration"},
      {"homogenization/layered_square.json", "periodic_cell", "/cell", "gird", "cell.gird"},
      {"homogenization/auxetic_2d.json", "cell_design", "/design/optimizer", "max_iteration",
       "design.optimizer.max_iteration"},
      {"material_fit/spline_fit_neo_hookean.json", "material_fit", "/initial", "presett", "initial.presett"},
      {"", "damping_design", "/damping_design/plate", "lenght", "damping_design.plate.lenght"},
      {"meshless_capsule.json", "meshless", "/meshless", "spacng", "meshless.spacng"},
      {"interlocking_square_design.json", "interlocking", "/interlocking/cell", "patern", "interlocking.cell.patern"},
      {"rig/arm_jiggle.json", "rig_dynamics", "/rig_dynamics", "time_stp", "rig_dynamics.time_stp"},
      {"interlocking_macro_drape.json", "macro_sheet", "/interlocking_macro/drape", "widht",
       "interlocking_macro.drape.widht"},
  };
  int checked = 0;
  for (const auto& c : cases) {
    nlohmann::json document =
        c.scene.empty() ? damping : read_scene_document(testing::kScenesDir + "/" + c.scene);
    document[nlohmann::json::json_pointer(c.object)][c.key] = 1;
    const std::string path = folder / (c.kind + ".json");
    std::ofstream(path) << dump_json(document);
    const SceneFile file = read_scene_file(path);
    const SceneKind& kind = recognise_scene_kind(file.document);
    ASSERT_EQ(kind.name, c.kind) << path;
    // The same document in memory: its messages name what the caller calls it.
    const SceneFile memory = scene_from_document(document, "in memory", folder.str());
    for (const KindVerb& verb : kind.verbs) {
      for (const SceneFile* given : {&file, &memory}) {
        const std::string error = handler_error(kind, verb, *given, folder / "out");
        const std::string expected = given->source + ": " + c.path + ": unknown key (allowed here: ";
        EXPECT_EQ(error.substr(0, expected.size()), expected) << c.kind << " " << verb.verb << ": " << error;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 2 * 33);  // every verb of every kind, from its file and from memory
}

TEST(SceneKinds, AFileAndADocumentInMemory) {
  const TempFolder folder("scene_kinds_file");
  const std::string path = folder / "bar.json";
  std::ofstream(path) << R"({"rods": []})";
  const SceneFile file = read_scene_file(path);
  EXPECT_TRUE(file.given());
  EXPECT_EQ(file.source, path);
  EXPECT_EQ(file.directory(), folder.str());
  EXPECT_EQ(file.name(), "bar");
  EXPECT_EQ(file.default_out_dir(), "out/bar");
  EXPECT_EQ(file.node().source(), path);

  const SceneFile memory = scene_from_text(R"({"name": "mine", "rods": []})", "", "meshes");
  EXPECT_TRUE(memory.given());
  EXPECT_EQ(memory.path, "");
  EXPECT_EQ(memory.source, "(scene)");
  EXPECT_EQ(memory.directory(), "meshes");
  EXPECT_EQ(memory.name(), "mine");
  EXPECT_EQ(scene_from_document(nlohmann::json::object(), "doc").name(), "scene");
  EXPECT_FALSE(SceneFile{}.given());  // the command line without a scene file

  try {
    scene_from_text("{\"rods\": [}", "broken");
    ADD_FAILURE() << "bad JSON accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("broken: invalid JSON", 0), 0u) << e.what();
  }
  EXPECT_THROW(read_scene_file(folder / "missing.json"), SceneError);
}

}  // namespace
}  // namespace tailor::scene_kinds_test
