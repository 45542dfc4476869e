// The inverse section of scenes: typed parsing with defaults, the design groups and maps built
// against the mesh, and every kind of bad input as one SceneError naming the key path.
#include "problems/fem/inverse_scene.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "../support/temp_folder.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "scene_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::inverse_scene_test {
namespace {

namespace fs = std::filesystem;

// Per-element log E of the small box (E = 1000), observed on its x = 2 face with E = 1200, and
// a little smoothness.
const std::string kInverse = R"({
    "design": {"parameter": "youngs_modulus", "granularity": "per_element", "min": 100, "max": 1e5},
    "objective": [
      {"type": "synthetic_observations", "vertices": {"plane": {"axis": "x", "value": 2}}, "youngs_modulus": 1200},
      {"type": "smoothness", "weight": 0.01}
    ]
  })";

std::string inverse_scene(const std::string& inverse = kInverse) {
  return testing::with("\"solver\": {\"load_steps\": 1}",
                       "\"solver\": {\"load_steps\": 1},\n  \"inverse\": " + inverse);
}

// kInverse with the first `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to) {
  return testing::with(from, to, kInverse);
}

// The SceneError message of parsing `inverse` and building its problem, or "" when valid.
std::string inverse_error(const std::string& inverse, const std::string& directory = "") {
  try {
    build_inverse_problem(parse_scene(inverse_scene(inverse), "test.json", directory));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(InverseScene, ParsesTypedValuesAndDefaults) {
  const Scene scene = parse_scene(inverse_scene(), "test.json", "");
  ASSERT_TRUE(scene.inverse);
  const InverseSpec& spec = *scene.inverse;
  EXPECT_EQ(spec.design.granularity, DesignGranularity::per_element);
  EXPECT_EQ(spec.design.map, DesignMap::log);  // default
  EXPECT_EQ(spec.design.min, 100.0);
  EXPECT_EQ(spec.design.max, 1e5);
  EXPECT_FALSE(spec.design.initial);
  ASSERT_EQ(spec.objective.size(), 2u);
  EXPECT_EQ(spec.objective[0].type(), "synthetic_observations");
  EXPECT_EQ(spec.objective[0].key, "inverse.objective[0]");
  EXPECT_EQ(spec.objective[0].weight, 1.0);  // default
  const auto& synthetic = *spec.objective[0].settings_as<SyntheticObservationsTerm>();
  EXPECT_EQ(synthetic.youngs_modulus.value, 1200.0);
  EXPECT_EQ(synthetic.noise, 0.0);
  const auto& smoothness = *spec.objective[1].settings_as<SmoothnessTerm>();
  EXPECT_TRUE(smoothness.logarithmic);
  EXPECT_EQ(smoothness.weighting, AdjacencyWeighting::unit);
  EXPECT_EQ(spec.objective[1].weight, 0.01);
  EXPECT_FALSE(spec.ground_truth);
  EXPECT_EQ(spec.optimizer.backend, OptimizerBackend::nlopt_lbfgs);
  EXPECT_EQ(spec.optimizer.max_iterations, OptimizerOptions{}.max_iterations);
  EXPECT_EQ(spec.gradcheck.halvings, TaylorTestOptions{}.halvings);

  const Scene plain = parse_scene(testing::small_box_scene(), "test.json", "");
  EXPECT_FALSE(plain.inverse);
}

TEST(InverseScene, ParsesOptimizerGradcheckAndEveryTermType) {
  const std::string inverse = R"({
    "design": {"parameter": "youngs_modulus", "granularity": "per_material", "map": "identity", "min": 10,
               "initial": 500},
    "objective": [
      {"type": "target_displacements", "weight": 2, "vertices": {"list": [1, 2]}, "displacement": [0.1, 0, 0]},
      {"type": "synthetic_observations", "vertices": {"list": [3]}, "youngs_modulus": {"materials": [900]},
       "noise": 0.01, "seed": 4},
      {"type": "smoothness", "on": "value", "weighting": "facet"},
      {"type": "tikhonov", "weight": 0.5, "prior": 800}
    ],
    "ground_truth": {"youngs_modulus": 900},
    "optimizer": {"backend": "ipopt", "max_iterations": 7, "gradient_tolerance": 1e-6, "objective_tolerance": 1e-9,
                  "step_tolerance": 1e-10, "time_limit": 30, "exact_hessian": true},
    "gradcheck": {"seed": 3, "initial_step": 0.1, "halvings": 6}
  })";
  const Scene scene = parse_scene(inverse_scene(inverse), "test.json", "");
  const InverseSpec& spec = *scene.inverse;
  EXPECT_EQ(spec.design.granularity, DesignGranularity::per_material);
  EXPECT_EQ(spec.design.map, DesignMap::identity);
  EXPECT_EQ(spec.design.initial, 500.0);
  EXPECT_FALSE(spec.design.max);
  const auto& target = *spec.objective[0].settings_as<TargetDisplacementsTerm>();
  EXPECT_EQ(target.displacement, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_EQ(spec.objective[0].weight, 2.0);
  const auto& synthetic = *spec.objective[1].settings_as<SyntheticObservationsTerm>();
  EXPECT_EQ(synthetic.youngs_modulus.per_material, std::vector<double>{900});
  EXPECT_EQ(synthetic.noise, 0.01);
  EXPECT_EQ(synthetic.seed, 4u);
  const auto& smoothness = *spec.objective[2].settings_as<SmoothnessTerm>();
  EXPECT_FALSE(smoothness.logarithmic);
  EXPECT_EQ(smoothness.weighting, AdjacencyWeighting::facet_over_distance);
  EXPECT_EQ(spec.objective[3].settings_as<TikhonovTerm>()->prior, 800.0);
  ASSERT_TRUE(spec.ground_truth);
  EXPECT_EQ(spec.ground_truth->value, 900.0);
  EXPECT_EQ(spec.optimizer.backend, OptimizerBackend::ipopt);
  EXPECT_EQ(spec.optimizer.max_iterations, 7);
  EXPECT_EQ(spec.optimizer.gradient_tolerance, 1e-6);
  EXPECT_EQ(spec.optimizer.objective_tolerance, 1e-9);
  EXPECT_EQ(spec.optimizer.step_tolerance, 1e-10);
  EXPECT_EQ(spec.optimizer.time_limit_seconds, 30.0);
  EXPECT_TRUE(spec.optimizer.exact_hessian);
  EXPECT_EQ(spec.gradcheck.seed, 3u);
  EXPECT_EQ(spec.gradcheck.initial_step, 0.1);
  EXPECT_EQ(spec.gradcheck.halvings, 6);

  // Built: one variable (one material), z = E, the truth from both sources (they agree).
  const auto problem = build_inverse_problem(scene);
  EXPECT_EQ(problem->num_design(), 1);
  EXPECT_EQ(problem->z0, Vector::Constant(1, 500.0));
  EXPECT_EQ(problem->bounds.lower, Vector::Constant(1, 10.0));
  EXPECT_TRUE(std::isinf(problem->bounds.upper[0]));
  EXPECT_EQ(problem->truth, Eigen::VectorXd::Constant(problem->setup.mesh.num_elements(), 900.0));
  EXPECT_EQ(problem->truth_key, "inverse.ground_truth.youngs_modulus");
  ASSERT_EQ(problem->terms.size(), 4u);
  EXPECT_EQ(problem->terms[2].coefficient, 1.0);  // regularization: the weight as given
  // Data terms are relative: weight / |u*|^2.
  EXPECT_NEAR(problem->terms[0].coefficient, 2.0 / (2 * 0.1 * 0.1), 1e-12);
}

TEST(InverseScene, DesignGroupsPerRegionAndPerMaterial) {
  // The unit cube with regions 1 (E = 1e5) and 2 (E = 1e6).
  const std::string cube = R"({
    "mesh": {"file": "unit_cube_v2.msh"},
    "materials": [
      {"elements": {"region": 1}, "model": "linear", "youngs_modulus": 1e5, "poisson_ratio": 0.3},
      {"elements": {"region": 2}, "model": "linear", "youngs_modulus": 1e6, "poisson_ratio": 0.3}
    ],
    "dirichlet": [{"vertices": {"plane": {"axis": "z", "value": 0}}}],
    "loads": {"tractions": [{"faces": {"plane": {"axis": "z", "value": 1}}, "traction": [0, 0, -1e3]}]},
    "inverse": {
      "design": {"parameter": "youngs_modulus", "granularity": "per_region"},
      "objective": [{"type": "target_displacements", "vertices": {"plane": {"axis": "z", "value": 1}},
                     "displacement": [0, 0, -0.01]}]
    }
  })";
  const std::string meshes = std::string(::tailor::testing::test_data_dir()) + "/meshes";
  const auto by_region = build_inverse_problem(parse_scene(cube, "cube.json", meshes));
  EXPECT_EQ(by_region->design_labels, (std::vector<std::string>{"region 1", "region 2"}));
  EXPECT_NEAR(by_region->z0[0], std::log(1e5), 1e-12);
  EXPECT_NEAR(by_region->z0[1], std::log(1e6), 1e-12);
  EXPECT_TRUE(by_region->bounds.lower.size() == 0 && by_region->bounds.upper.size() == 0);
  // The map reproduces the materials' moduli element by element.
  const Vector p = by_region->parameterization->apply(by_region->z0);
  const int ne = by_region->setup.mesh.num_elements();
  EXPECT_LT((p.head(ne) - by_region->setup.youngs_modulus).cwiseAbs().maxCoeff(), 1e-6);

  const auto by_material = build_inverse_problem(
      parse_scene(testing::with("per_region", "per_material", cube), "cube.json", meshes));
  EXPECT_EQ(by_material->design_labels, (std::vector<std::string>{"materials[0]", "materials[1]"}));
  EXPECT_EQ(by_material->design_of_element, by_material->setup.element_material);

  const auto by_element = build_inverse_problem(parse_scene(inverse_scene(), "test.json", ""));
  EXPECT_EQ(by_element->num_design(), by_element->setup.mesh.num_elements());
  EXPECT_EQ(by_element->bounds.lower, Vector::Constant(by_element->num_design(), std::log(100.0)));
  EXPECT_EQ(by_element->bounds.upper, Vector::Constant(by_element->num_design(), std::log(1e5)));
}

struct BadInverse {
  std::string inverse;
  std::string message;  // expected substring of the SceneError
};

TEST(InverseScene, EveryErrorNamesTheKeyPath) {
  const std::string synthetic =
      R"({"type": "synthetic_observations", "vertices": {"plane": {"axis": "x", "value": 2}}, "youngs_modulus": 1200})";
  const std::vector<BadInverse> cases = {
      {edited("\"design\"", "\"desgin\""),
       "test.json: inverse.desgin: unknown key (allowed here: design, objective, ground_truth, optimizer, "
       "gradcheck)"},
      {R"({"objective": [)" + synthetic + "]}", "test.json: inverse: missing required key \"design\""},
      {edited("\"parameter\": \"youngs_modulus\"", "\"parameter\": \"poisson_ratio\""),
       "test.json: inverse.design.parameter: only \"youngs_modulus\" can be designed (for now), got "
       "\"poisson_ratio\""},
      {edited("\"per_element\"", "\"per_vertex\""),
       "test.json: inverse.design.granularity: expected one of per_element, per_region, per_material, modes, "
       "got \"per_vertex\""},
      {edited("\"max\": 1e5", "\"max\": 1e5, \"map\": \"exp\""),
       "test.json: inverse.design.map: expected one of log, identity, got \"exp\""},
      {edited("\"min\": 100", "\"min\": 0"),
       "test.json: inverse.design.min: with the log map (z = log E) the bound must be > 0, got 0"},
      {edited("\"min\": 100", "\"map\": \"identity\", \"min\": -1"),
       "test.json: inverse.design.min: expected a number >= 0 (Young's modulus), got -1"},
      {edited("\"max\": 1e5", "\"max\": 50"), "test.json: inverse.design.max: must be > min (100), got 50"},
      {edited("\"max\": 1e5", "\"max\": 1e5, \"initial\": 1e6"),
       "test.json: inverse.design.initial: lies outside the bounds [100, 100000]"},
      {edited("\"min\": 100", "\"min\": 2000"),
       "test.json: inverse.design: the initial Young's modulus 1000 of element 0 (from the scene's "
       "materials) lies "
       "outside the bounds [2000, 100000]; give \"initial\" or widen the bounds"},
      {R"({"design": {"parameter": "youngs_modulus", "granularity": "per_element"}, "objective": {"terms": 1}})",
       "test.json: inverse.objective: expected an array, got an object"},
      {edited("\"weight\": 0.01", "\"weight\": -1"),
       "test.json: inverse.objective[1].weight: expected a number >= 0, got -1"},
      {edited("\"type\": \"smoothness\"", "\"type\": \"smooth\""),
       "test.json: inverse.objective[1].type: expected one of handles, observations, smoothness, "
       "synthetic_observations, target_displacements, tikhonov, got \"smooth\""},
      {edited("\"youngs_modulus\": 1200", "\"youngs_modulus\": 1200, \"nosie\": 0.1"),
       "test.json: inverse.objective[0].nosie: unknown key (allowed here: type, weight, vertices, "
       "youngs_modulus, "
       "noise, seed)"},
      {edited("\"youngs_modulus\": 1200", "\"youngs_modulus\": 1200, \"noise\": -0.1"),
       "test.json: inverse.objective[0].noise: expected a number >= 0, got -0.1"},
      {edited("\"youngs_modulus\": 1200", "\"youngs_modulus\": \"stiff\""),
       "test.json: inverse.objective[0].youngs_modulus: expected a number > 0, {\"materials\": [one value "
       "per material]}, {\"file\": path} (one value per element) or {\"value\": E0, \"gradient\": [...], "
       "\"inclusions\": [...]}, got a string \"stiff\""},
      {edited("\"youngs_modulus\": 1200", "\"youngs_modulus\": {\"materials\": [1200, 900]}"),
       "test.json: inverse.objective[0].youngs_modulus.materials: expected one value per materials[] entry "
       "(1), got 2"},
      {edited("{\"plane\": {\"axis\": \"x\", \"value\": 2}}", "{\"list\": []}"),
       "test.json: inverse.objective[0].vertices.list: selects no vertices (the list is empty)"},
      {edited("\"value\": 2}}", "\"value\": 5}}"),
       "test.json: inverse.objective[0].vertices: selects no vertices"},
      {edited(synthetic, R"({"type": "tikhonov", "prior": 1000})"),
       "test.json: inverse.objective: needs at least one data term (handles, observations, "
       "synthetic_observations, target_displacements)"},
      {edited(synthetic,
              R"({"type": "target_displacements", "vertices": {"list": [1]}, "displacement": [0, 1]})"),
       "test.json: inverse.objective[0].displacement: expected 3 components (the mesh is 3D), got 2"},
      {edited("\"min\": 100, \"max\": 1e5", "\"map\": \"identity\""),
       "test.json: inverse.objective[1]: smoothness on log E needs E > 0"},
      {edited("\"objective\"", "\"ground_truth\": {\"youngs_modulus\": 1000}, \"objective\""),
       "test.json: inverse.objective[0].youngs_modulus: differs from the true Young's modulus given by "
       "inverse.ground_truth.youngs_modulus"},
      {edited("\"design\"", "\"optimizer\": {\"backend\": \"lbfgs\"}, \"design\""),
       "test.json: inverse.optimizer.backend: unknown optimizer back-end 'lbfgs' (known: ceres_lbfgs, ceres_least_squares"},
      {edited("\"design\"", "\"optimizer\": {\"backend\": \"ceres_lbfgs\"}, \"design\""),
       "test.json: inverse.optimizer.backend: ceres_lbfgs does not support bounds"},
      {edited("\"design\"", "\"optimizer\": {\"exact_hessian\": true}, \"design\""),
       "test.json: inverse.optimizer.exact_hessian: only the ipopt back-end uses exact Hessians (the "
       "back-end is "
       "nlopt_lbfgs)"},
      {edited("\"design\"", "\"optimizer\": {\"backend\": \"ipopt\", \"exact_hessian\": 1}, \"design\""),
       "test.json: inverse.optimizer.exact_hessian: expected true or false, got 1"},
      {edited("\"design\"", "\"optimizer\": {\"max_iterations\": 0}, \"design\""),
       "test.json: inverse.optimizer.max_iterations: expected an integer >= 1, got 0"},
      {edited("\"design\"", "\"gradcheck\": {\"halvings\": 3}, \"design\""),
       "test.json: inverse.gradcheck.halvings: expected an integer >= 4, got 3"},
  };
  for (const BadInverse& c : cases) {
    SCOPED_TRACE(c.inverse);
    const std::string message = inverse_error(c.inverse);
    EXPECT_NE(message.find(c.message), std::string::npos)
        << "got: " << message << "\nexpected: " << c.message;
  }
  EXPECT_EQ(inverse_error(kInverse), "");
}

TEST(InverseScene, NoInverseSectionIsAnError) {
  try {
    build_inverse_problem(parse_scene(testing::small_box_scene(), "test.json", ""));
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("test.json: (top level): the scene has no \"inverse\" section"),
              std::string::npos)
        << e.what();
  }
}

TEST(InverseScene, ObservationFilesAreCheckedLineByLine) {
  const fs::path folder = testing::unique_temp_path("tailor_inverse_obs");
  fs::create_directories(folder);
  const std::string observations = R"({
    "design": {"parameter": "youngs_modulus", "granularity": "per_material"},
    "objective": [{"type": "observations", "file": "obs.txt"}]
  })";
  const auto error_with = [&](const std::string& text) {
    std::ofstream(folder / "obs.txt") << text;
    return inverse_error(observations, folder.string());
  };
  EXPECT_EQ(error_with("# vertex ux uy uz\n3 0.1 0 0\n4 0.2 0 0  # right end\n"), "");
  EXPECT_NE(error_with("3 0.1 0 0\n3 0.2 0 0\n")
                .find("inverse.objective[0].file: '" + (folder / "obs.txt").string() +
                      "' line 2: vertex 3 is observed twice (also on line 1)"),
            std::string::npos);
  EXPECT_NE(error_with("3 0.1 0\n4 0.2 0 0\n").find("line 2: expected 'vertex ux uy' or 'vertex ux uy uz'"),
            std::string::npos);
  EXPECT_NE(
      error_with("3 0.1 0\n").find("expected 3 displacement components per line (the mesh is 3D), got 2"),
      std::string::npos);
  EXPECT_NE(error_with("999 0.1 0 0\n").find("vertex 999 does not exist (the mesh has 45 vertices)"),
            std::string::npos);
  EXPECT_NE(error_with("").find("holds no observations"), std::string::npos);
  fs::remove_all(folder);
}

}  // namespace
}  // namespace tailor::inverse_scene_test
