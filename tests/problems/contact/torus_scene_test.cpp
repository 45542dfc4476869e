// Torus chain scenes: the shipped scene runs its steps without intersections and writes every
// torus per frame; a static chain's report carries the closed-form pair forces (each pair holds
// the weight below it); the mesh model runs the same chain; bad input gets a SceneError naming
// the key path.
#include "problems/contact/torus_scene.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::torus_scene_test {
namespace {

const std::string kScenes = std::string(::tailor::testing::test_data_dir()) + "/../../scenes/contact/";

std::string temporary_directory(const std::string& name) {
  const auto dir = testing::unique_temp_path("tailor_tori_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The scene's text as `tailor` parses it.
TorusSceneSpec parse_torus(const std::string& text, const std::string& source) {
  return parse_torus_scene(scene_from_text(text, source).node());
}

TEST(TorusScene, ShippedChainSwingsWithoutIntersectionsAndWritesEveryTorusPerFrame) {
  const TorusSceneSpec spec = parse_torus(read_text(kScenes + "torus_chain.json"), "torus_chain.json");
  ASSERT_TRUE(spec.dynamic);
  const std::string out = temporary_directory("shipped");
  const TorusSimulateRun run = simulate_torus_scene(spec, out, nullptr);
  EXPECT_TRUE(run.completed());
  EXPECT_EQ(run.steps, spec.steps);
  EXPECT_EQ(run.intersections, 0);
  EXPECT_GT(run.min_distance, 0.0);
  const int frames = spec.steps / spec.output_every + 1;
  for (int b = 0; b < spec.chain.count; ++b)
    for (int f = 0; f < frames; ++f) {
      char name[64];
      std::snprintf(name, sizeof name, "/link_%d_%04d.vtu", b, f);
      EXPECT_TRUE(std::filesystem::exists(out + name)) << name;
    }
  const nlohmann::json report = parse_json(std::ifstream(out + "/report.json"));
  testing::expect_report_header(out + "/report.json");
  EXPECT_EQ(report["per_step"].size(), static_cast<std::size_t>(spec.steps));
  EXPECT_EQ(report["intersections"], 0);
}

// Static by relaxation with 10 s steps, at rest when no DOF moves more than 1e-7 in a step (the
// mesh model's facets let the links creep slowly towards their rest).
const char* kStatic = R"({"tori": {"count": 4, "major_radius": 1.0, "minor_radius": 0.2, "segments": [24, 6],
  "mode": "static", "contact_model": "MODEL", "static_time_step": 10, "static_tolerance": 1e-7}})";

std::string static_scene(const std::string& model) {
  std::string s = kStatic;
  s.replace(s.find("MODEL"), 5, model);
  return s;
}

TEST(TorusScene, StaticChainReportsTheWeightBelowEachPair) {
  const TorusSceneSpec spec = parse_torus(static_scene("implicit"), "static.json");
  const std::string out = temporary_directory("static");
  const TorusSimulateRun run = simulate_torus_scene(spec, out, nullptr);
  ASSERT_TRUE(run.completed());
  const nlohmann::json report = parse_json(std::ifstream(out + "/report.json"));
  const double weight = report["bodies"][1]["mass"].get<double>() * 9.81;
  ASSERT_EQ(report["pairs"].size(), 3u);
  for (const nlohmann::json& pair : report["pairs"]) {
    const int below = 4 - pair["b"].get<int>();
    EXPECT_NEAR(pair["force_on_b"][2].get<double>(), below * weight, 1e-6 * 4 * weight);
  }
}

TEST(TorusScene, MeshModelHangsTheSameChainWithoutIntersections) {
  // Reference: the implicit model's equilibrium; the triangulated tori (24 x 6) differ from the
  // implicit ones by their chord sag, so the link heights agree to a fraction of the tube radius.
  const std::string out_mesh = temporary_directory("mesh"), out_implicit = temporary_directory("implicit");
  const TorusSimulateRun mesh =
      simulate_torus_scene(parse_torus(static_scene("mesh"), "m.json"), out_mesh, nullptr);
  const TorusSimulateRun implicit =
      simulate_torus_scene(parse_torus(static_scene("implicit"), "i.json"), out_implicit, nullptr);
  ASSERT_TRUE(mesh.completed());
  ASSERT_TRUE(implicit.completed());
  const nlohmann::json a = parse_json(std::ifstream(out_mesh + "/report.json"));
  const nlohmann::json b = parse_json(std::ifstream(out_implicit + "/report.json"));
  for (int k = 1; k < 4; ++k) {
    const double za = a["bodies"][k]["position"][2].get<double>(),
                 zb = b["bodies"][k]["position"][2].get<double>();
    EXPECT_NEAR(za, zb, 0.1) << k;
    EXPECT_NE(za, zb) << k;  // two different models
  }
}

TEST(TorusScene, EllipticTubesAreReadAndHangWithTheWeightBelowEachPair) {
  std::string text = static_scene("implicit");
  text.replace(text.find("\"minor_radius\": 0.2"), 19, "\"minor_radius\": 0.2, \"minor_radius_1\": 0.3");
  const TorusSceneSpec spec = parse_torus(text, "elliptic.json");
  EXPECT_EQ(spec.chain.shape.minor_radius_1, 0.3);
  const std::string out = temporary_directory("elliptic");
  const TorusSimulateRun run = simulate_torus_scene(spec, out, nullptr);
  ASSERT_TRUE(run.completed());
  EXPECT_EQ(run.intersections, 0);
  const nlohmann::json report = parse_json(std::ifstream(out + "/report.json"));
  const double mass = report["bodies"][1]["mass"].get<double>(), weight = mass * 9.81;
  EXPECT_NEAR(mass, 1000.0 * 2.0 * M_PI * M_PI * 1.0 * 0.2 * 0.3, 1e-9);  // rho 2 pi^2 R r r1
  ASSERT_EQ(report["pairs"].size(), 3u);
  for (const nlohmann::json& pair : report["pairs"]) {
    const int below = 4 - pair["b"].get<int>();
    EXPECT_NEAR(pair["force_on_b"][2].get<double>(), below * weight, 1e-6 * 4 * weight);
  }
  // Equal to minor_radius: the circular tube (r1 follows r).
  text = static_scene("implicit");
  text.replace(text.find("\"minor_radius\": 0.2"), 19, "\"minor_radius\": 0.2, \"minor_radius_1\": 0.2");
  EXPECT_EQ(parse_torus(text, "circular.json").chain.shape.minor_radius_1, 0.0);
}

TEST(TorusScene, BadInputNamesTheKey) {
  auto message = [](const std::string& text) {
    try {
      parse_torus(text, "bad.json");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(
      message(R"({"tori": {"count": 3, "major_radius": 1, "minor_radius": 0.2, "minor_radius_1": -0.3}})")
          .find("tori.minor_radius_1"),
      std::string::npos);
  EXPECT_NE(message(R"({"tori": {"count": 3, "major_radius": 1, "minor_radius": 0.2, "spacing": 1.7}})")
                .find("tori.spacing"),
            std::string::npos);
  EXPECT_NE(
      message(R"({"tori": {"count": 3, "major_radius": 1, "minor_radius": 1.2}})").find("tori.minor_radius"),
      std::string::npos);
  EXPECT_NE(message(R"({"tori": {"count": 1, "major_radius": 1, "minor_radius": 0.2}})").find("tori.count"),
            std::string::npos);
  EXPECT_NE(message(R"({"tori": {"count": 3, "major_radius": 1, "minor_radius": 0.2, "colour": 1}})")
                .find("colour"),
            std::string::npos);
}

// tailor gradcheck on the shipped three-torus scene: the adjoint gradient of the link centres'
// objective in the masses and radii, through the static equilibrium with both pairs in contact
// (reference: re-solved equilibria at perturbed parameters, the Taylor remainder must fall at
// rate >= 1.9 after a first-order regime); with the gradient scaled by 1.001 the same test fails.
TEST(TorusScene, GradcheckOfTheShippedSceneThroughActiveContact) {
  const TorusSceneSpec spec =
      parse_torus(read_text(kScenes + "torus_gradcheck.json"), "torus_gradcheck.json");
  const TorusGradcheckRun run = gradcheck_torus_scene(spec, temporary_directory("gradcheck"), {}, nullptr);
  std::printf("%s", run.taylor.table().c_str());
  EXPECT_EQ(run.active_pairs, 2);
  EXPECT_EQ(run.intersections, 0);
  EXPECT_GT(run.min_distance, 0.0);
  EXPECT_TRUE(run.taylor.passed()) << run.taylor.table();
  EXPECT_GE(run.taylor.rate1, 1.9);
  EXPECT_NEAR(run.taylor.rate0, 1.0, 0.1);
  EXPECT_TRUE(run.passed());

  TorusGradcheckOptions wrong;
  wrong.gradient_scale = 1.001;
  const TorusGradcheckRun bad =
      gradcheck_torus_scene(spec, temporary_directory("gradcheck_wrong"), wrong, nullptr);
  EXPECT_EQ(bad.taylor.status, TaylorStatus::failed) << bad.taylor.table();
}

TEST(TorusScene, GradcheckRefusesDynamicAndMeshScenes) {
  TorusSceneSpec spec = parse_torus(read_text(kScenes + "torus_chain.json"), "torus_chain.json");
  EXPECT_THROW(gradcheck_torus_scene(spec, temporary_directory("gradcheck_dynamic"), {}, nullptr),
               SceneError);
  spec = parse_torus(read_text(kScenes + "torus_gradcheck.json"), "torus_gradcheck.json");
  spec.options.model = tori::ContactModel::mesh;
  EXPECT_THROW(gradcheck_torus_scene(spec, temporary_directory("gradcheck_mesh"), {}, nullptr), SceneError);
}

// The same gradcheck with elliptic tubes (r1 = 0.3 held, R and r the radius parameters): the
// distance's derivatives in r at fixed r1 (elliptic_distance.hpp) through the same adjoint.
TEST(TorusScene, GradcheckOfAnEllipticChainThroughActiveContact) {
  nlohmann::json scene = parse_json(read_text(kScenes + "torus_gradcheck.json"));
  scene["tori"]["minor_radius_1"] = 0.3;
  const TorusSceneSpec spec = parse_torus(dump_json(scene), "elliptic_gradcheck.json");
  const TorusGradcheckRun run =
      gradcheck_torus_scene(spec, temporary_directory("gradcheck_elliptic"), {}, nullptr);
  std::printf("%s", run.taylor.table().c_str());
  EXPECT_EQ(run.active_pairs, 2);
  EXPECT_EQ(run.intersections, 0);
  EXPECT_TRUE(run.taylor.passed()) << run.taylor.table();
  EXPECT_GE(run.taylor.rate1, 1.9);
  EXPECT_TRUE(run.passed());
  TorusGradcheckOptions wrong;
  wrong.gradient_scale = 1.001;
  const TorusGradcheckRun bad =
      gradcheck_torus_scene(spec, temporary_directory("gradcheck_elliptic_wrong"), wrong, nullptr);
  EXPECT_EQ(bad.taylor.status, TaylorStatus::failed) << bad.taylor.table();
}

// tailor gradcheck on the shipped placement scene: the gradient in the fixed top link's pose
// (T, w), masses and radii held, through both active pairs (reference: re-solved equilibria at
// perturbed placements; rate ~1 then >= 1.9); with the gradient scaled by 1.001 it fails. The
// same with every parameter selected (masses, radii and the placement in one direction).
TEST(TorusScene, GradcheckOfTheAnchorPlacementThroughActiveContact) {
  const TorusSceneSpec spec =
      parse_torus(read_text(kScenes + "torus_placement_gradcheck.json"), "placement_gradcheck.json");
  EXPECT_FALSE(spec.gradcheck_masses);
  EXPECT_FALSE(spec.gradcheck_radii);
  EXPECT_TRUE(spec.gradcheck_placements);
  const std::string out = temporary_directory("gradcheck_placement");
  const TorusGradcheckRun run = gradcheck_torus_scene(spec, out, {}, nullptr);
  std::printf("%s", run.taylor.table().c_str());
  EXPECT_EQ(run.active_pairs, 2);
  EXPECT_EQ(run.intersections, 0);
  EXPECT_TRUE(run.taylor.passed()) << run.taylor.table();
  EXPECT_NEAR(run.taylor.rate0, 1.0, 0.1);
  EXPECT_GE(run.taylor.rate1, 1.9);
  EXPECT_TRUE(run.passed());
  const nlohmann::json report = parse_json(std::ifstream(out + "/gradcheck.json"));
  testing::expect_report_header(out + "/gradcheck.json");
  EXPECT_EQ(report["parameters"], "the placement (T, w) of each fixed link");

  TorusGradcheckOptions wrong;
  wrong.gradient_scale = 1.001;
  const TorusGradcheckRun bad =
      gradcheck_torus_scene(spec, temporary_directory("gradcheck_placement_wrong"), wrong, nullptr);
  EXPECT_EQ(bad.taylor.status, TaylorStatus::failed) << bad.taylor.table();

  nlohmann::json scene = parse_json(read_text(kScenes + "torus_placement_gradcheck.json"));
  scene["tori"]["gradcheck"]["parameters"] = {"placements", "radii", "masses"};
  const TorusSceneSpec all = parse_torus(dump_json(scene), "all_gradcheck.json");
  const TorusGradcheckRun every =
      gradcheck_torus_scene(all, temporary_directory("gradcheck_all"), {}, nullptr);
  std::printf("%s", every.taylor.table().c_str());
  EXPECT_TRUE(every.passed()) << every.taylor.table();
  EXPECT_GE(every.taylor.rate1, 1.9);
}

TEST(TorusScene, GradcheckParametersAreCheckedWithTheirKey) {
  auto message = [](const std::string& gradcheck, bool fix_first) {
    nlohmann::json scene = parse_json(read_text(kScenes + "torus_placement_gradcheck.json"));
    scene["tori"]["gradcheck"] = parse_json(gradcheck);
    scene["tori"]["fix_first"] = fix_first;
    try {
      parse_torus(dump_json(scene), "bad.json");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(R"({"parameters": ["placements"]})", false).find("tori.gradcheck.parameters"),
            std::string::npos);
  EXPECT_NE(message(R"({"parameters": []})", true).find("tori.gradcheck.parameters"), std::string::npos);
  EXPECT_NE(message(R"({"parameters": ["poses"]})", true).find("tori.gradcheck.parameters"),
            std::string::npos);
  EXPECT_NE(message(R"({"parameters": ["radii", "radii"]})", true).find("twice"), std::string::npos);
  EXPECT_NE(message(R"({"seed": 2})", true).find("seed"), std::string::npos);
  EXPECT_EQ(message(R"({"parameters": ["masses"]})", false), "no error");
}

// The shipped friction scene: parsed with friction and adaptive kappa, every step converged with
// no crossing, the report carrying kappa (raised from its start, never lowered) and friction.
TEST(TorusScene, ShippedFrictionChainSwingsWithAdaptiveStiffness) {
  const TorusSceneSpec spec =
      parse_torus(read_text(kScenes + "torus_chain_friction.json"), "torus_chain_friction.json");
  ASSERT_TRUE(spec.dynamic);
  EXPECT_DOUBLE_EQ(spec.options.friction.coefficient, 0.3);
  EXPECT_DOUBLE_EQ(spec.options.friction.velocity_threshold, 1e-3);
  EXPECT_TRUE(spec.options.stiffness_control.adaptive);
  const std::string out = temporary_directory("friction");
  const TorusSimulateRun run = simulate_torus_scene(spec, out, nullptr);
  EXPECT_TRUE(run.completed());
  EXPECT_EQ(run.steps, spec.steps);
  EXPECT_GT(run.min_distance, 0.0);
  const nlohmann::json report = parse_json(read_text(out + "/report.json"));
  EXPECT_TRUE(report["adaptive_stiffness"].get<bool>());
  EXPECT_GE(report["stiffness"].get<double>(), report["initial_stiffness"].get<double>());
  EXPECT_DOUBLE_EQ(report["friction"]["coefficient"].get<double>(), 0.3);
  double previous = 0.0;
  int sliding = 0;
  for (const auto& step : report["per_step"]) {
    EXPECT_GE(step["stiffness"].get<double>(), previous);
    previous = step["stiffness"].get<double>();
    sliding += step["friction_sliding"].get<int>();
  }
  EXPECT_GT(sliding, 0);  // the links slide on each other: friction acts
}

TEST(TorusScene, FrictionAndStiffnessKeysAreChecked) {
  auto message = [](const std::string& keys) {
    try {
      parse_torus(R"({"tori": {"count": 3, "major_radius": 1, "minor_radius": 0.2, )" + keys + "}}",
                  "bad.json");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Static scenes are frictionless: friction is refused there.
  EXPECT_NE(message(R"("friction": 0.3)").find("tori.friction"), std::string::npos);
  EXPECT_EQ(message(R"("friction": 0.3, "mode": "dynamic")"), "no error");
  EXPECT_EQ(message(R"("friction": 0, "mode": "static")"), "no error");
  EXPECT_NE(message(R"("friction": -0.3, "mode": "dynamic")").find("tori.friction"), std::string::npos);
  EXPECT_NE(message(R"("friction_velocity": 1e-3, "mode": "dynamic")").find("tori.friction_velocity"),
            std::string::npos);
  EXPECT_NE(message(R"("stiffness": "soft")").find("tori.stiffness"), std::string::npos);
  EXPECT_NE(message(R"("stiffness": 1e9, "min_stiffness": 1e8)").find("tori.min_stiffness"),
            std::string::npos);
  EXPECT_NE(message(R"("min_stiffness": 1e9, "max_stiffness": 1e8)").find("tori.max_stiffness"),
            std::string::npos);
  // Absent or "adaptive": adaptive; a number fixes kappa.
  const auto spec = [](const std::string& keys) {
    return parse_torus(R"({"tori": {"count": 3, "major_radius": 1, "minor_radius": 0.2)" + keys + "}}",
                       "ok.json");
  };
  EXPECT_TRUE(spec("").options.stiffness_control.adaptive);
  EXPECT_TRUE(spec(R"(, "stiffness": "adaptive", "min_stiffness": 1e8)").options.stiffness_control.adaptive);
  EXPECT_DOUBLE_EQ(spec(R"(, "min_stiffness": 1e8)").options.stiffness_control.min_stiffness, 1e8);
  EXPECT_FALSE(spec(R"(, "stiffness": 1e9)").options.stiffness_control.adaptive);
  EXPECT_DOUBLE_EQ(spec(R"(, "stiffness": 1e9)").options.stiffness, 1e9);
}

// A static chain without a fixed link is free as a whole: refused before relaxing (before, it
// fell for 6 relaxation steps of 1 s until Newton's iteration limit, then reported that it did
// not come to rest), for simulate and gradcheck, naming the file and the key. Dynamic chains
// without a fixed link stay allowed (they fall).
TEST(TorusScene, StaticChainWithoutAFixedLinkIsRefused) {
  nlohmann::json scene = parse_json(read_text(kScenes + "torus_gradcheck.json"));
  scene["tori"]["fix_first"] = false;
  const TorusSceneSpec spec = parse_torus(dump_json(scene), "free_chain.json");
  for (int verb = 0; verb < 2; ++verb) {
    try {
      if (verb == 0)
        simulate_torus_scene(spec, temporary_directory("free_chain"), nullptr);
      else
        gradcheck_torus_scene(spec, temporary_directory("free_chain_gc"), {}, nullptr);
      ADD_FAILURE() << "a free static chain was relaxed";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("free_chain.json: tori.fix_first: no link is fixed, so the chain is "
                                           "free to move as one rigid body"),
                std::string::npos)
          << e.what();
    }
  }
  scene["tori"]["mode"] = "dynamic";
  scene["tori"]["steps"] = 1;
  const TorusSimulateRun run = simulate_torus_scene(parse_torus(dump_json(scene), "falling_chain.json"),
                                                    temporary_directory("falling_chain"), nullptr);
  EXPECT_EQ(run.steps, 1);
}

}  // namespace
}  // namespace tailor::torus_scene_test
