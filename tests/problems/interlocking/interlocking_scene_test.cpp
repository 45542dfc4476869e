// Inverse design of interlocking limits: the exact limit derivative (implicit function theorem on
// the lock-up state) against the Taylor test, in the radii and the lattice vectors; a recovery
// test; the scene kind's outputs and its refusal of unknown keys.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "adjoint/taylor_test.hpp"
#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/periodic_mesh_elements.hpp"
#include "problems/interlocking/interlocking_scene.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_kinds.hpp"

namespace tailor::interlocking_scene_test {
namespace {

using namespace interlocking;

const tori::TorusShape kRing{1.0, 0.2};

// s*(z) of one path, z = (all master radii, the lattice matrix column by column), each
// evaluation continuing the last lock-up state by the augmented Newton.
class LimitFunction final : public ReducedFunctional {
 public:
  LimitFunction(RigidCellSpec base, LoadPath path, double gradient_scale = 1.0)
      : base_(with_parameters(base, master_radii(base), base.lattice)), path_(path), scale_(gradient_scale) {
    const PeriodicRigidCell cell(base_);
    const LimitPoint p = find_limit(cell, path_, rest_equilibrium(cell));
    EXPECT_TRUE(p.locked && p.refined) << p.status;
    y_ = p.y;
    s_ = p.strain;
    a_ = p.critical_a;
    b_ = p.critical_b;
  }
  int size() const override { return static_cast<int>(master_radii(base_).size()) + 4; }
  Vector z0() const {
    Vector z(size());
    z << master_radii(base_), base_.lattice.reshaped();
    return z;
  }
  double value(const Vector& z) override { return evaluate(z, nullptr); }
  double value_and_gradient(const Vector& z, Vector& gradient) override { return evaluate(z, &gradient); }

 private:
  double evaluate(const Vector& z, Vector* gradient) {
    const int n = size() - 4;
    const Eigen::Matrix2d L = z.tail<4>().reshaped(2, 2);
    const PeriodicRigidCell cell(with_parameters(base_, z.head(n), L));
    const RefineResult r =
        refine_limit(cell, path_, path_lock() * cell.activation_distance(), a_, b_, y_, s_);
    if (!r.converged) throw EvaluationError(r.message);
    if (gradient) {
      const LimitGradient g = limit_gradient(cell, path_, a_, b_, r.y, r.strain);
      gradient->resize(size());
      *gradient << g.radii, g.lattice.reshaped();
      *gradient *= scale_;
    }
    return r.strain;
  }
  static double path_lock() { return LimitOptions{}.lock_fraction; }
  RigidCellSpec base_;
  LoadPath path_;
  double scale_;
  Vector y_;
  double s_ = 0.0;
  int a_ = -1, b_ = -1;
};

TaylorTestOptions taylor_options() {
  TaylorTestOptions o;
  o.initial_step = 1e-4;
  o.seed = 3;
  return o;
}

// A threefold mail stretched at 30 degrees locks on four pairs at once (links of two directions):
// its limit is a genuinely nonlinear function of every radius and lattice entry.
TEST(InterlockingDesign, LimitDerivativePassesTheTaylorTestInRadiiAndLattice) {
  LimitFunction limit(threefold_cell(kRing, {1.0, 0.18}, 1.5), uniaxial_path(M_PI / 6.0));
  const TaylorTestResult r = taylor_test(limit, limit.z0(), taylor_options());
  std::printf("%s", r.table().c_str());
  EXPECT_TRUE(r.passed()) << r.message;
  EXPECT_GE(r.rate1, 1.9);
  EXPECT_NEAR(r.rate0, 1.0, 0.1);
  // The same test rejects the gradient scaled by 1.001.
  LimitFunction wrong(threefold_cell(kRing, {1.0, 0.18}, 1.5), uniaxial_path(M_PI / 6.0), 1.001);
  EXPECT_FALSE(taylor_test(wrong, wrong.z0(), taylor_options()).passed());
}

// Principal stretch at 45 degrees in the square net (both chains lock together) and the lattice.
TEST(InterlockingDesign, SquareNetLimitDerivativeAt45Degrees) {
  LimitFunction limit(square_ring_cell(kRing, {1.05, 0.2}, kRing, 1.5), principal_path(M_PI / 4.0));
  const TaylorTestResult r = taylor_test(limit, limit.z0(), taylor_options());
  std::printf("%s", r.table().c_str());
  EXPECT_TRUE(r.passed()) << r.message;
}

// Recovery: the limits of a known design (x links R = 1.1, y links R = 0.95) as targets, designed
// from R = 1 for both: the optimizer recovers the known radii.
TEST(InterlockingDesign, RecoversAKnownDesignFromItsLimits) {
  // The same d_hat in both (its default follows the smallest R, which differs between them).
  RigidCellSpec known = square_ring_cell(kRing, {1.1, 0.2}, {0.95, 0.2}, 1.5);
  known.activation_distance = 1e-3;
  RigidCellSpec start = square_ring_cell(kRing, kRing, kRing, 1.5);
  start.activation_distance = 1e-3;
  std::vector<LimitTarget> targets;
  {
    const PeriodicRigidCell cell(known);
    const Vector y = rest_equilibrium(cell);
    for (double angle : {0.0, 0.5 * M_PI}) {
      const LimitPoint p = find_limit(cell, uniaxial_path(angle), y);
      targets.push_back({uniaxial_path(angle), p.strain});
    }
  }
  std::vector<DesignVariable> variables = {{1, true, 0.85, 1.2}, {2, true, 0.85, 1.2}};
  LimitDesignFunctional functional(start, variables, targets, {});
  OptimizerOptions options;
  options.backend = OptimizerBackend::nlopt_mma;
  options.max_iterations = 60;
  options.gradient_tolerance = 1e-12;
  options.checkpoint_every = 0;
  const OptimizerResult result = minimize(functional, functional.initial_design(), functional.bounds(),
                                          functional.margin_constraints(0.02, 0.3), options);
  std::printf("recovered R_x = %.10f, R_y = %.10f (known 1.1, 0.95), objective %.3e, %d evaluations\n",
              result.z[0], result.z[1], result.objective, result.evaluations);
  EXPECT_NEAR(result.z[0], 1.1, 1e-6);
  EXPECT_NEAR(result.z[1], 0.95, 1e-6);
}

// Bending recovery: the curvature limits (single curvature along x and along y) of a square-net
// disc patch (the centre node and its four links free, the four nearest nodes prescribed) whose x
// links have R = 1.1 and y links R = 0.95 as targets, designed from R = 1.05 and 1: the variables
// name the tiling's link elements, so every copy in the patch follows; MMA recovers the radii.
TEST(InterlockingDesign, RecoversAKnownPatchFromItsBendingLimits) {
  RigidCellSpec known = disc_patch(square_ring_cell(kRing, {1.1, 0.2}, {0.95, 0.2}, 1.5), 3.1, 0.7);
  known.activation_distance = 1e-3;
  RigidCellSpec start = disc_patch(square_ring_cell(kRing, {1.05, 0.2}, kRing, 1.5), 3.1, 0.7);
  start.activation_distance = 1e-3;
  ASSERT_EQ(start.elements.size(), 9u);
  std::vector<LimitTarget> targets;
  {
    const PeriodicRigidCell cell(known);
    const Vector y = rest_equilibrium(cell);
    for (double angle : {0.0, 0.5 * M_PI}) {
      const LimitPoint p = find_limit(cell, uniaxial_path(angle), y);
      ASSERT_TRUE(p.locked && p.refined) << p.status;
      targets.push_back({uniaxial_path(angle), p.strain});
    }
  }
  std::vector<DesignVariable> variables = {{1, true, 0.9, 1.15}, {2, true, 0.9, 1.15}};
  // Coarse bisection steps (the augmented Newton refines every limit to round-off anyway).
  LimitOptions limit_options;
  limit_options.initial_step = 0.05;
  limit_options.tolerance = 1e-3;
  LimitDesignFunctional functional(start, variables, targets, limit_options);
  OptimizerOptions options;
  options.backend = OptimizerBackend::nlopt_mma;
  options.max_iterations = 60;
  options.gradient_tolerance = 1e-12;
  options.checkpoint_every = 0;
  const OptimizerResult result = minimize(functional, functional.initial_design(), functional.bounds(),
                                          functional.margin_constraints(0.02, 0.3), options);
  std::printf("bending targets %.10f, %.10f; recovered R_x = %.10f, R_y = %.10f (known 1.1, 0.95), objective %.3e, "
              "%d evaluations\n",
              targets[0].strain, targets[1].strain, result.z[0], result.z[1], result.objective, result.evaluations);
  EXPECT_NEAR(result.z[0], 1.1, 1e-6);
  EXPECT_NEAR(result.z[1], 0.95, 1e-6);
}

// The margin constraint's gradient (pair distances at the rest placement) against differences.
TEST(InterlockingDesign, MarginConstraintGradient) {
  std::vector<DesignVariable> variables = {{0, true, 0.5, 1.5}, {0, false, 0.1, 0.3}, {1, true, 0.5, 1.5}};
  const LimitDesignFunctional functional(square_ring_cell(kRing, kRing, kRing, 1.5), variables,
                                         {{uniaxial_path(0.0), 0.1}}, {});
  const std::vector<Constraint> constraints = functional.margin_constraints(0.02, 0.5);
  ASSERT_FALSE(constraints.empty());
  const Vector z = functional.initial_design();
  for (const Constraint& c : constraints) {
    Vector g;
    c.evaluate(z, &g);
    for (int i = 0; i < z.size(); ++i) {
      Vector zp = z, zm = z;
      zp[i] += 1e-6;
      zm[i] -= 1e-6;
      const double fd = (c.evaluate(zp, nullptr) - c.evaluate(zm, nullptr)) / 2e-6;
      EXPECT_NEAR(g[i], fd, 1e-6) << c.name << " variable " << i;
    }
  }
}

const char* kScene = R"({
  "name": "small",
  "interlocking": {
    "cell": {"pattern": "square_rings", "spacing": 1.5, "node": {"major_radius": 1.0, "minor_radius": 0.2},
             "link": {"major_radius": 1.0, "minor_radius": 0.2}},
    "boundary": {"loading": "principal", "directions": 4, "max_strain": 0.5}
  }
})";

TEST(InterlockingScene, SimulateWritesTheBoundaryPlotAndSamples) {
  const std::string out = (std::filesystem::temp_directory_path() / "tailor_interlocking_scene_test").string();
  std::filesystem::remove_all(out);
  const SceneFile file = scene_from_text(kScene, "small.json");
  InterlockingScene scene = parse_interlocking_scene(file.node());
  scene.name = "small";
  EXPECT_TRUE(run_interlocking_boundary(scene, scene.cell, out, nullptr));
  for (const char* f : {"report.json", "boundary.png", "sample_0.vtu", "sample_3.vtu"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  const nlohmann::json& samples = report["boundary"]["samples"];
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_TRUE(samples[0]["locked"].get<bool>());
  EXPECT_NEAR(samples[0]["eps_xx"].get<double>(), (1.6 - 0.0005) / 1.5 - 1.0, 1e-9);
  EXPECT_GT(samples[0]["certified_clearance"].get<double>(), 0.0);
  EXPECT_FALSE(samples[0]["active_pairs"].empty());
}

TEST(InterlockingScene, UnknownKeysAndBadCellsAreRefusedWithTheirPath) {
  std::string text = kScene;
  text.replace(text.find("\"max_strain\""), 12, "\"max_stran\"");
  try {
    parse_interlocking_scene(scene_from_text(text, "bad.json").node());
    FAIL() << "accepted an unknown key";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("interlocking.boundary.max_stran"), std::string::npos) << e.what();
  }
  std::string overlap = kScene;
  overlap.replace(overlap.find("\"spacing\": 1.5"), 14, "\"spacing\": 1.1");  // nodes 2.2 apart overlap
  EXPECT_THROW(parse_interlocking_scene(scene_from_text(overlap, "overlap.json").node()), SceneError);
}

// Mesh bodies in a cell: the chain of rings meshed 12 x 6 through the cell's "mesh" key, one
// uniaxial direction; the report has the lock-up at the closed form within the mesh's chordal
// bound, the intersection check's counts, the cell's mesh sources and the VTU; unknown mesh keys,
// a missing mesh file and a design on a mesh cell are refused with their key path.
const char* kMeshScene = R"({
  "name": "meshed",
  "interlocking": {
    "cell": {"pattern": "chain", "spacing": 1.5, "node": {"major_radius": 1.0, "minor_radius": 0.2},
             "activation_distance": 0.001, "mesh": {"torus_segments": [12, 6]}},
    "boundary": {"loading": "uniaxial", "directions": 1, "max_strain": 0.3, "tolerance": 1e-5}
  }
})";

TEST(InterlockingScene, MeshCellWritesTheBoundaryAndRefusesBadMeshKeys) {
  const std::string out = (std::filesystem::temp_directory_path() / "tailor_interlocking_mesh_scene_test").string();
  std::filesystem::remove_all(out);
  InterlockingScene scene = parse_interlocking_scene(scene_from_text(kMeshScene, "meshed.json").node());
  EXPECT_TRUE(is_mesh_cell(scene.cell));
  EXPECT_TRUE(run_interlocking_boundary(scene, scene.cell, out, nullptr));
  for (const char* f : {"report.json", "boundary.png", "sample_0.vtu"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  const nlohmann::json& sample = report["boundary"]["samples"][0];
  EXPECT_TRUE(sample["locked"].get<bool>());
  // Closed form 2 (R - r) - d_hat / 2 over s0, minus 1; the mesh's bound 2 delta / s0 is 0.09.
  EXPECT_NEAR(sample["eps_xx"].get<double>(), (1.6 - 0.0005) / 1.5 - 1.0, 1e-4);
  EXPECT_EQ(sample["mesh_intersection_check"]["intersecting"].get<long>(), 0);
  EXPECT_GT(sample["mesh_intersection_check"]["triangle_pairs_tested"].get<long>(), 0);
  EXPECT_EQ(report["boundary"]["cell"]["elements"][0]["mesh"]["source"].get<std::string>(), "torus 12 x 6");
  EXPECT_TRUE(report["boundary"]["all_certified_apart"].get<bool>());

  const auto refused = [](std::string text, const std::string& from, const std::string& to, const char* path) {
    text.replace(text.find(from), from.size(), to);
    try {
      parse_interlocking_scene(scene_from_text(text, "bad_mesh.json").node());
      ADD_FAILURE() << "accepted " << to;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("bad_mesh.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  refused(kMeshScene, "\"torus_segments\"", "\"torus_segmnts\"", "interlocking.cell.mesh.torus_segmnts");
  refused(kMeshScene, "[12, 6]", "[12, 2]", "interlocking.cell.mesh.torus_segments");
  const std::string file_scene = R"({"interlocking": {"cell": {"pattern": "elements", "lattice": [[3, 0], [0, 15]],
      "elements": [{"mesh": {"file": "no_such_ring.obj"}, "position": [0, 0, 0]}]}}})";
  refused(file_scene, "no_such_ring", "no_such_ring", "interlocking.cell.elements[0].mesh.file");
  refused(kMeshScene, "\"boundary\"", "\"design\": {}, \"boundary\"", "interlocking.design");
  refused(kMeshScene, "\"boundary\": {", "\"boundary\": {\"single_curvature\": true, ",
          "interlocking.boundary.single_curvature");
}

// Periodic single curvature as an option of the sweep: 0 and 90 degrees bend the square net to
// the same refined limit (its symmetry), reported as curvatures; the option is refused with its
// path for principal loading and for bending patches.
TEST(InterlockingScene, SingleCurvatureSweepAndItsRefusals) {
  std::string text = kScene;
  text.replace(text.find("\"loading\": \"principal\", \"directions\": 4"), 39,
               "\"loading\": \"uniaxial\", \"single_curvature\": true, \"directions\": 2, \"vtu\": false");
  const std::string out = (std::filesystem::temp_directory_path() / "tailor_interlocking_curvature_test").string();
  std::filesystem::remove_all(out);
  InterlockingScene scene = parse_interlocking_scene(scene_from_text(text, "curved.json").node());
  ASSERT_TRUE(scene.boundary.single_curvature);
  scene.name = "curved";
  EXPECT_TRUE(run_interlocking_boundary(scene, scene.cell, out, nullptr));
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  const nlohmann::json& samples = report["boundary"]["samples"];
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_TRUE(samples[0]["refined"].get<bool>() && samples[1]["refined"].get<bool>());
  EXPECT_NEAR(samples[0]["kappa_xx"].get<double>(), samples[1]["kappa_yy"].get<double>(), 1e-9);
  EXPECT_GT(samples[0]["certified_clearance"].get<double>(), 0.0);
  std::string principal = text;
  principal.replace(principal.find("\"uniaxial\""), 10, "\"principal\"");
  try {
    parse_interlocking_scene(scene_from_text(principal, "principal.json").node());
    FAIL() << "accepted single_curvature with principal loading";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("interlocking.boundary.single_curvature"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tailor::interlocking_scene_test
