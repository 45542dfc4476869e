// Scene parsing and validation: the example scenes parse, and every kind of bad input is one
// SceneError that names the scene and the JSON key path.
#include "problems/fem/scene.hpp"
#include "problems/scene_kinds.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "problems/fem/builtin_scenes.hpp"
#include "problems/fem/static_scene.hpp"
#include "scene_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::scene_test {
namespace {

const std::string kScenes = std::string(::tailor::testing::test_data_dir()) + "/../../scenes";

// The SceneError message of parsing and setting up `json`, or "" when it is valid.
std::string scene_error(const std::string& json) {
  try {
    const Scene scene = parse_scene(json, "test.json", "");
    setup_static_scene(scene);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, ParsesTheCantileverExample) {
  const Scene scene = read_scene(kScenes + "/cantilever.json");
  EXPECT_EQ(scene.name, "cantilever");
  EXPECT_EQ(scene.mesh.kind, MeshSpec::Kind::box);
  EXPECT_EQ(scene.mesh.cells, Eigen::Vector3i(30, 3, 3));
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].model, MaterialKind::neo_hookean);
  EXPECT_EQ(scene.materials[0].elements.kind, ElementSelector::Kind::all);
  ASSERT_EQ(scene.dirichlet.size(), 1u);
  EXPECT_EQ(scene.dirichlet[0].vertices.kind, VertexSelector::Kind::plane);
  ASSERT_EQ(scene.loads.tractions.size(), 1u);
  EXPECT_EQ(scene.loads.tractions[0].traction, Eigen::Vector3d(0, 0, -300));
  EXPECT_EQ(scene.solver.newton.max_iterations, 50);

  // The built-in default job is the same scene.
  const Scene builtin = builtin_cantilever();
  EXPECT_EQ(builtin.mesh.cells, scene.mesh.cells);
  EXPECT_EQ(builtin.mesh.max, scene.mesh.max);
  EXPECT_EQ(builtin.materials[0].youngs_modulus, scene.materials[0].youngs_modulus);
  EXPECT_EQ(builtin.loads.tractions[0].traction, scene.loads.tractions[0].traction);
  EXPECT_EQ(builtin.solver.newton.hessian, scene.solver.newton.hessian);
  EXPECT_EQ(builtin.solver.newton.max_iterations, scene.solver.newton.max_iterations);
}

TEST(Scene, ParsesThePlateExample) {
  const Scene scene = read_scene(kScenes + "/plate_2d.json");
  EXPECT_EQ(scene.mesh.kind, MeshSpec::Kind::rectangle);
  ASSERT_EQ(scene.materials.size(), 2u);
  EXPECT_EQ(scene.materials[1].elements.kind, ElementSelector::Kind::box);
  ASSERT_TRUE(scene.loads.gravity.has_value());
  EXPECT_EQ(*scene.loads.gravity, Eigen::Vector2d(0, -9.81));
  EXPECT_EQ(scene.solver.load_steps, 2);
  const StaticSetup setup = setup_static_scene(scene);
  EXPECT_EQ(setup.dim(), 2);
  EXPECT_LT(setup.nodal_forces.sum(), 0.0);  // weight points down
}

// Every FEM scene (kinds static and dynamic) shipped at the top of scenes/; the other kinds there
// (meshless, interlocking) have their own tests.
TEST(Scene, EveryExampleSceneSetsUp) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const std::string kind = recognise_scene_kind(read_scene_file(entry.path().string()).document).name;
    if (kind != "static" && kind != "dynamic") continue;
    const Scene scene = read_scene(entry.path().string());
    EXPECT_FALSE(scene.name.empty());
    const StaticSetup setup = setup_static_scene(scene);
    EXPECT_GT(setup.mesh.num_elements(), 0);
    EXPECT_FALSE(setup.fixed_dofs.empty());
    ++count;
  }
  EXPECT_GE(count, 2);
}

TEST(Scene, DefaultsComeFromNewtonOptions) {
  const Scene scene = parse_scene(testing::small_box_scene(), "test.json", "");
  const NewtonOptions defaults;
  EXPECT_EQ(scene.solver.newton.max_iterations, defaults.max_iterations);
  EXPECT_EQ(scene.solver.newton.relative_tolerance, defaults.relative_tolerance);
  EXPECT_EQ(scene.solver.newton.hessian, defaults.hessian);
  EXPECT_EQ(scene.solver.newton.reuse_factorization, defaults.reuse_factorization);
  EXPECT_EQ(defaults.reuse_factorization, FactorReuse::automatic);
  const auto reuse = [](const std::string& value) {
    return parse_scene(
               testing::with("\"load_steps\": 1", "\"load_steps\": 1, \"reuse_factorization\": " + value),
               "test.json", "")
        .solver.newton.reuse_factorization;
  };
  EXPECT_EQ(reuse("true"), FactorReuse::on);
  EXPECT_EQ(reuse("false"), FactorReuse::off);
  EXPECT_EQ(reuse("\"auto\""), FactorReuse::automatic);
  EXPECT_EQ(scene.solver.load_steps, 1);
  EXPECT_EQ(scene.materials[0].density, 0.0);
  EXPECT_EQ(scene_error(testing::small_box_scene()), "");
}

struct BadScene {
  const char* what;
  std::string json;
  std::string expected;  // substring of the message
};

// Test names show the case, not the bytes of the struct.
void PrintTo(const BadScene& bad, std::ostream* os) { *os << bad.what; }

class SceneValidation : public ::testing::TestWithParam<BadScene> {};

TEST_P(SceneValidation, NamesTheKeyPath) {
  const std::string message = scene_error(GetParam().json);
  EXPECT_NE(message.find(GetParam().expected), std::string::npos) << "message: " << message;
  EXPECT_EQ(message.rfind("test.json: ", 0), 0u) << "message: " << message;
}

using testing::small_box_scene;
using testing::with;

INSTANTIATE_TEST_SUITE_P(
    BadInput, SceneValidation,
    ::testing::Values(
        BadScene{"unknown_key", with("\"poisson_ratio\": 0.3", "\"poisson_ratio\": 0.3, \"colour\": \"red\""),
                 "materials[0].colour: unknown key"},
        BadScene{"unknown_top_key", with("\"name\": \"box\"", "\"name\": \"box\", \"meshes\": {}"),
                 "meshes: unknown key"},
        BadScene{"wrong_type", with("\"youngs_modulus\": 1000", "\"youngs_modulus\": \"1000\""),
                 "materials[0].youngs_modulus: expected a number > 0, got a string \"1000\""},
        BadScene{"nu_half", with("\"poisson_ratio\": 0.3", "\"poisson_ratio\": 0.5"),
                 "materials[0].poisson_ratio: expected a number in (-1, 0.5), got 0.5"},
        BadScene{"negative_E", with("\"youngs_modulus\": 1000", "\"youngs_modulus\": -1"),
                 "materials[0].youngs_modulus: expected a number > 0, got -1"},
        BadScene{"negative_density",
                 with("\"poisson_ratio\": 0.3", "\"poisson_ratio\": 0.3, \"density\": -2"),
                 "materials[0].density: expected a number >= 0, got -2"},
        BadScene{"missing_model", with("\"model\": \"linear\", ", ""),
                 "materials[0]: missing required key \"model\""},
        BadScene{"bad_model", with("\"model\": \"linear\"", "\"model\": \"rubber\""),
                 "materials[0].model: expected one of corotated, linear, neo_hookean, stvk, spline, got "
                 "\"rubber\""},
        BadScene{
            "missing_mesh",
            with("\"mesh\": {\"box\": {\"min\": [0, 0, 0], \"max\": [2, 1, 1], \"cells\": [4, 2, 2]}},", ""),
            "(top level): missing required key \"mesh\""},
        BadScene{"cells_length", with("\"cells\": [4, 2, 2]", "\"cells\": [4, 2]"),
                 "mesh.box.cells: expected 3 cell counts"},
        BadScene{"cells_zero", with("\"cells\": [4, 2, 2]", "\"cells\": [4, 0, 2]"),
                 "mesh.box.cells[1]: expected an integer >= 1, got 0"},
        BadScene{"box_corners", with("\"max\": [2, 1, 1]", "\"max\": [2, -1, 1]"),
                 "mesh.box.max: every entry must be"},
        BadScene{"gravity_length", with("\"tractions\"", "\"gravity\": [0, -9.81], \"tractions\""),
                 "loads.gravity: expected 3 components (the mesh is 3D), got 2"},
        BadScene{"traction_length", with("\"traction\": [1, 0, 0]", "\"traction\": [1, 0, 0, 0]"),
                 "loads.tractions[0].traction: expected an array of 2 or 3 numbers, got an array of 4"},
        BadScene{"empty_plane", with("\"axis\": \"x\", \"value\": 0}", "\"axis\": \"x\", \"value\": 5}"),
                 "dirichlet[0].vertices: selects no vertices"},
        BadScene{"empty_faces", with("\"value\": 2}", "\"value\": 2.5}"),
                 "loads.tractions[0].faces: selects no vertices"},
        BadScene{"empty_list", with("{\"plane\": {\"axis\": \"x\", \"value\": 0}}", "{\"list\": []}"),
                 "dirichlet[0].vertices.list: selects no vertices"},
        BadScene{"vertex_out_of_range",
                 with("{\"plane\": {\"axis\": \"x\", \"value\": 0}}", "{\"list\": [0, 4000]}"),
                 "dirichlet[0].vertices: vertex 4000 does not exist"},
        BadScene{
            "two_selectors",
            with("{\"plane\": {\"axis\": \"x\", \"value\": 0}}", "{\"list\": [0], \"box\": {}}"),
            "dirichlet[0].vertices: expected an object with exactly one of the keys plane, box, list, file"},
        BadScene{"bad_axis", with("\"axis\": \"x\", \"value\": 0}", "\"axis\": \"w\", \"value\": 0}"),
                 "dirichlet[0].vertices.plane.axis: expected one of x, y, z, got \"w\""},
        BadScene{"bad_component", with("\"components\": [0]", "\"components\": [3]"),
                 "dirichlet[0].components[0]: expected a component 0, 1 or 2, got 3"},
        BadScene{"uncovered",
                 with("\"elements\": \"all\"",
                      "\"elements\": {\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}}"),
                 ": materials: element "},
        BadScene{"covered_twice",
                 with("\"materials\": [",
                      "\"materials\": [{\"elements\": \"all\", \"model\": \"stvk\", "
                      "\"youngs_modulus\": 5, \"poisson_ratio\": 0.1}, "),
                 "materials[1].elements: element 0 is covered by materials[0] already"},
        BadScene{"missing_region", with("\"elements\": \"all\"", "\"elements\": {\"region\": 7}"),
                 "materials[0].elements: selects no elements (no element has region 7"},
        BadScene{"bad_hessian", with("\"load_steps\": 1", "\"load_steps\": 1, \"hessian\": \"full\""),
                 "solver.hessian: expected one of adaptive, exact, projected, got \"full\""},
        BadScene{"bad_load_steps", with("\"load_steps\": 1", "\"load_steps\": 0"),
                 "solver.load_steps: expected an integer >= 1, got 0"},
        BadScene{"bad_reuse", with("\"load_steps\": 1", "\"load_steps\": 1, \"reuse_factorization\": 1"),
                 "solver.reuse_factorization: expected true, false or \"auto\", got 1"},
        BadScene{"bad_tolerance", with("\"load_steps\": 1", "\"load_steps\": 1, \"relative_tolerance\": 0"),
                 "solver.relative_tolerance: expected a number in (0, 1), got 0"},
        BadScene{"invalid_json", with("\"name\": \"box\",", "\"name\": \"box\""), "invalid JSON"},
        BadScene{"huge_box", with("\"cells\": [4, 2, 2]", "\"cells\": [400, 400, 400]"),
                 "mesh.box.cells: 3.84e+08 tets would need at least"},
        BadScene{"int_overflow_box", with("\"cells\": [4, 2, 2]", "\"cells\": [100000, 100000, 100000]"),
                 "more elements than int indices can count"},
        BadScene{"number_overflow", with("\"youngs_modulus\": 1000", "\"youngs_modulus\": 1e400"),
                 "a number is out of the range of double precision (at or after key \"youngs_modulus\")"},
        BadScene{"bad_factorization_threads",
                 with("\"load_steps\": 1", "\"load_steps\": 1, \"threads\": {\"factorization\": 2}"),
                 "solver.threads.factorization: expected 1"},
        BadScene{"not_an_object", "[1, 2]", "(top level): expected an object, got an array of 2"}),
    [](const ::testing::TestParamInfo<BadScene>& param_info) { return std::string(param_info.param.what); });

TEST(Scene, UncoveredElementIsNamed) {
  const std::string message = scene_error(
      with("\"elements\": \"all\"", "\"elements\": {\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}}"));
  EXPECT_NE(message.find("is covered by no material"), std::string::npos) << message;
}

TEST(Scene, MissingSceneFileIsASceneError) {
  try {
    read_scene("/nonexistent/beam.json");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/beam.json: cannot open"), std::string::npos)
        << e.what();
  }
}

TEST(Scene, AFolderIsNotASceneFile) {
  try {
    read_scene(kScenes);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder, not a scene file"), std::string::npos) << e.what();
  }
}

TEST(Scene, ThreadSettingsParse) {
  const Scene scene = parse_scene(
      with("\"load_steps\": 1", "\"load_steps\": 1, \"threads\": {\"assembly\": 2, \"factorization\": 0}"),
      "test.json", "");
  ASSERT_TRUE(scene.solver.threads.has_value());
  EXPECT_EQ(scene.solver.threads->assembly, 2);
  EXPECT_EQ(scene.solver.threads->blas, 0);
  EXPECT_EQ(scene.solver.threads->factorization, 0);
  EXPECT_FALSE(parse_scene(small_box_scene(), "test.json", "").solver.threads.has_value());
}

TEST(Scene, UnsupportedBodyIsRefusedNamingItsFreeMotions) {
  // The statically determinate supports of the small box pin it; a roller on x = 0 alone
  // leaves two translations and a rotation free.
  const Scene pinned = parse_scene(small_box_scene(), "test.json", "");
  EXPECT_NO_THROW(require_supported(pinned, setup_static_scene(pinned)));
  std::string text = small_box_scene();
  const auto begin = text.find("    {\"vertices\": {\"list\": [0]}");
  const auto end = text.find("  ],\n  \"loads\"");
  ASSERT_NE(begin, std::string::npos);
  text = text.substr(0, begin) + text.substr(end);
  text = with("\"components\": [0]},", "\"components\": [0]}", text);
  const Scene roller = parse_scene(text, "test.json", "");
  try {
    require_supported(roller, setup_static_scene(roller));
    FAIL() << "no error";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dirichlet: the supports leave the body free to move rigidly"), std::string::npos)
        << what;
    EXPECT_NE(what.find("translation along y"), std::string::npos) << what;
    EXPECT_NE(what.find("rotation about x"), std::string::npos) << what;
  }
}

TEST(Scene, MissingMeshFileIsAMeshError) {
  const Scene scene =
      parse_scene(with("{\"box\": {\"min\": [0, 0, 0], \"max\": [2, 1, 1], \"cells\": [4, 2, 2]}}",
                       "{\"file\": \"nope.msh\"}"),
                  "test.json", "/nonexistent");
  EXPECT_EQ(scene.mesh.file, "/nonexistent/nope.msh");  // relative to the scene's folder
  EXPECT_THROW(setup_static_scene(scene), MeshError);
}

}  // namespace
}  // namespace tailor::scene_test
