// FEM bodies in contact scenes (`fem_bodies` with the FEM scene's keys next to `rigid_bodies`):
//  - EmbeddedTerm (an FEM body's elasticity placed after the rigid DOFs) passes the derivative
//    checks, parameters included;
//  - Hertz contact (Johnson, "Contact Mechanics", 1985, section 4.2; Hertz 1882): an elastic body
//    with a paraboloidal end z = r^2 / (2 R) pressed by a force F onto a rigid plane touches it
//    over a disc of radius a = (3 F R / (4 E*))^(1/3), E* = E / (1 - nu^2), with the pressure
//    p0 sqrt(1 - r^2 / a^2), whose force-weighted mean of r^2 is 2 a^2 / 5. A quarter of the
//    body (symmetry planes x = 0, y = 0), linear elastic, on a graded tetrahedral mesh: the
//    contact force equals the load, a from the nodal contact forces matches Hertz within the
//    discretization error stated below, and nothing intersects;
//  - the shipped scene runs; bad FEM body input is a SceneError naming fem_bodies[i].
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/temp_folder.hpp"
#include "adjoint/derivative_check.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"
#include "problems/contact/embedded_term.hpp"
#include "problems/contact/rigid_scene.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::fem_contact_scene_test {
namespace {

const std::string kScenes = std::string(::tailor::testing::test_data_dir()) + "/../../scenes/contact/";

std::string temporary_directory(const std::string& name) {
  const auto dir = testing::unique_temp_path("tailor_fem_contact_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// The scene file as `tailor simulate` reads it (named after its file without a "name").
RigidSceneSpec read_rigid_scene(const std::string& path) {
  const SceneFile file = read_scene_file(path);
  RigidSceneSpec spec = parse_rigid_scene(file.node(), file.directory());
  spec.name = file.name();
  return spec;
}

TEST(EmbeddedTerm, ElasticityAfterOtherDofsPassesDerivativeChecks) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0.5, 0.5), 2, 1, 1);
  const int m = mesh.num_elements(), n = 3 * mesh.num_vertices();
  const ElasticTerm<3> elastic(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m);
  const int x0 = 12, p0 = 3;  // 12 other DOFs before, 3 other parameters before
  const EmbeddedTerm term(elastic, x0, n, p0, 2 * m);
  Vector x = Vector::Random(x0 + n + 5), p(p0 + 2 * m + 1);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    x.segment<3>(x0 + 3 * v) = mesh.rest_positions.row(v).transpose() + 0.05 * Eigen::Vector3d::Random();
  p.setConstant(7.0);
  p.segment(p0, m).setConstant(1e3);
  p.segment(p0 + m, m).setConstant(0.3);
  const EnergyTermCheck check = check_energy_term(term, x, p);
  EXPECT_TRUE(check.passed()) << check.table();
  // Nothing leaks outside its block.
  Vector g = Vector::Zero(x.size());
  term.add_gradient(x, p, g);
  EXPECT_EQ(g.head(x0).norm(), 0.0);
  EXPECT_EQ(g.tail(5).norm(), 0.0);
}

// Nodes of a graded axis: `fine` cells of width `width` from 0, then `coarse` cells growing
// geometrically up to `length`.
std::vector<double> graded_axis(double width, int fine, int coarse, double length) {
  std::vector<double> x;
  for (int i = 0; i <= fine; ++i) x.push_back(i * width);
  // Growth ratio r with width (r + r^2 + ... + r^coarse) = length - fine width.
  double lo = 1.0, hi = 3.0;
  const double rest = length - fine * width;
  for (int it = 0; it < 200; ++it) {
    const double r = 0.5 * (lo + hi);
    double sum = 0, w = width;
    for (int i = 0; i < coarse; ++i) sum += (w *= r);
    (sum > rest ? hi : lo) = r;
  }
  double w = width;
  for (int i = 0; i < coarse; ++i) x.push_back(x.back() + (w *= lo));
  x.back() = length;
  return x;
}

// A quarter of a block (x, y in [0, half_width], height) whose bottom is the paraboloid
// z = r^2 / (2 R), graded towards the contact at the origin; written as a Medit file.
void write_lens_mesh(const std::string& path, double radius, double half_width, double height, double cell,
                     int fine_xy, int coarse_xy, int fine_z, int coarse_z) {
  const std::vector<double> X = graded_axis(cell, fine_xy, coarse_xy, half_width);
  const std::vector<double> Z = graded_axis(cell, fine_z, coarse_z, height);
  const int nx = static_cast<int>(X.size()) - 1, nz = static_cast<int>(Z.size()) - 1;
  Mesh mesh = box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(nx, nx, nz), nx, nx, nz);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const auto i = [&](int k) { return static_cast<std::size_t>(std::lround(mesh.rest_positions(v, k))); };
    const double x = X[i(0)], y = X[i(1)], z = Z[i(2)];
    mesh.rest_positions.row(v) << x, y, z + (1.0 - z / height) * (x * x + y * y) / (2.0 * radius);
  }
  std::ofstream out(path);
  out << "MeshVersionFormatted 1\nDimension 3\nVertices\n" << mesh.num_vertices() << "\n";
  out.precision(17);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    out << mesh.rest_positions(v, 0) << " " << mesh.rest_positions(v, 1) << " " << mesh.rest_positions(v, 2)
        << " 0\n";
  out << "Tetrahedra\n" << mesh.num_elements() << "\n";
  for (int e = 0; e < mesh.num_elements(); ++e)
    out << mesh.elements(e, 0) + 1 << " " << mesh.elements(e, 1) + 1 << " " << mesh.elements(e, 2) + 1 << " "
        << mesh.elements(e, 3) + 1 << " 0\n";
  out << "End\n";
}

TEST(FemContactScene, HertzContactOfAnElasticParaboloidOnARigidPlane) {
  const double R = 1.0, E = 1e5, nu = 0.3, a_target = 0.1, W = 0.5, H = 0.5, d_hat = 1e-4;
  const double E_star = E / (1 - nu * nu);
  const double F = 4.0 * E_star * a_target * a_target * a_target / (3.0 * R);  // full body's load
  const std::string dir = temporary_directory("hertz");
  write_lens_mesh(dir + "/lens.mesh", R, W, H, 0.015, 10, 6, 4, 7);
  nlohmann::json scene = {
      {"name", "hertz"},
      {"gravity", {0, 0, 0}},
      {"rigid_bodies",
       {{{"name", "plane"},
         {"primitive", "box"},
         {"size", {2, 2, 0.2}},
         {"position", {0, 0, -0.1 - 0.5 * d_hat}},
         {"fixed", true}}}},
      {"fem_bodies",
       {{{"name", "lens"},
         {"mesh", {{"file", "lens.mesh"}}},
         {"materials",
          {{{"elements", "all"}, {"model", "linear"}, {"youngs_modulus", E}, {"poisson_ratio", nu}}}},
         {"dirichlet",
          {{{"vertices", {{"plane", {{"axis", "x"}, {"value", 0}}}}}, {"components", {0}}},
           {{"vertices", {{"plane", {{"axis", "y"}, {"value", 0}}}}}, {"components", {1}}}}},
         {"loads",
          {{"tractions",
            {{{"faces", {{"plane", {{"axis", "z"}, {"value", H}}}}},
              {"traction", {0, 0, -F / 4 / (W * W)}}}}}}}}}},
      {"contact", {{"activation_distance", d_hat}}},
      {"newton", {{"max_iterations", 200}}}};
  std::ofstream(dir + "/hertz.json") << dump_json(scene, 2);
  const RigidSceneSpec spec = read_rigid_scene(dir + "/hertz.json");
  ASSERT_EQ(spec.fem_bodies.size(), 1u);
  const RigidSimulateRun run = simulate_rigid_scene(spec, dir + "/out", nullptr);
  ASSERT_TRUE(run.newton.converged()) << run.newton.report();
  EXPECT_EQ(run.intersections, 0);
  EXPECT_GT(run.min_distance, 0.0);
  // The plane carries the load (a quarter of F).
  EXPECT_NEAR(run.fem_contact_forces[0].z(), F / 4, 1e-6 * F);
  // Contact radius from the nodal contact forces of the lens: a^2 = 5/2 <r^2>_f.
  std::ifstream in(dir + "/out/report.json");
  const nlohmann::json report = parse_json(in);
  const int first_dof = 6;  // after the plane's rigid DOFs
  double weight = 0, moment = 0;
  for (Eigen::Index dof = first_dof; dof + 2 < run.state.size(); dof += 3) {
    const double fz = run.contact_forces[dof + 2];
    if (fz <= 0) continue;
    const double x = run.state[dof], y = run.state[dof + 1];
    weight += fz;
    moment += fz * (x * x + y * y);
  }
  const double a = std::sqrt(2.5 * moment / weight);
  const double a_hertz = std::cbrt(3 * F * R / (4 * E_star));
  std::printf(
      "Hertz: load %.4f N (quarter %.4f), contact force %.6f N, a = %.5f m, Hertz %.5f m (error %.1f%%), %d "
      "Newton iterations, kappa %.3g, min distance %.3g m, %d active pairs\n",
      F, F / 4, run.fem_contact_forces[0].z(), a, a_hertz, 100 * (a / a_hertz - 1), run.newton_iterations,
      run.stiffness, run.min_distance, run.active_pairs);
  // Discretization error: cells of 0.15 a under the contact, a block 5 a wide and deep.
  EXPECT_NEAR(a, a_hertz, 0.05 * a_hertz);
  EXPECT_EQ(report["fem_bodies"][0]["name"], "lens");
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/lens.vtu"));
}

// Statics: the block (FEM, 0.4 x 0.4 x 0.2 m, 1000 kg/m^3) carries its weight and the rigid
// sphere's net of what it receives from the sphere; the ground carries both.
TEST(FemContactScene, ShippedSoftBlockSceneCarriesItsLoad) {
  const RigidSceneSpec spec = read_rigid_scene(kScenes + "soft_block_on_ground.json");
  const RigidSimulateRun run = simulate_rigid_scene(spec, temporary_directory("shipped"), nullptr);
  ASSERT_TRUE(run.newton.converged()) << run.newton.report();
  EXPECT_EQ(run.intersections, 0);
  EXPECT_GT(run.min_distance, 0.0);
  const double g = 9.81, block = 1000 * 0.4 * 0.4 * 0.2 * g, sphere = spec.bodies[1].mass * g;
  EXPECT_NEAR(run.fem_contact_forces[0].z(), block, 1e-6 * block);
  EXPECT_NEAR(run.contact_forces[6 + 2], sphere, 1e-6 * sphere);
  EXPECT_NEAR(run.contact_forces[2], -(block + sphere), 1e-6 * (block + sphere));
}

void expect_scene_error(const std::string& json, const std::string& fragment) {
  try {
    const RigidSceneSpec spec =
        parse_rigid_scene(scene_from_text(json, "bad.json").node(), temporary_directory("bad"));
    simulate_rigid_scene(spec, temporary_directory("bad_out"), nullptr);
    FAIL() << "expected a SceneError containing '" << fragment << "'";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(FemContactScene, BadFemBodiesAreReportedWithContext) {
  const std::string ground =
      R"({"primitive": "box", "size": [2, 2, 1], "position": [0, 0, -0.5], "fixed": true})";
  const std::string block =
      R"("mesh": {"box": {"min": [0, 0, 0.001], "max": [1, 1, 1], "cells": [1, 1, 1]}})";
  expect_scene_error(R"({"rigid_bodies": [)" + ground + R"(], "fem_bodies": [{)" + block +
                         R"(, "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 1e5,
                             "poisson_ratio": 0.7}]}]})",
                     "bad.json: fem_bodies[0]: materials[0].poisson_ratio");
  expect_scene_error(R"({"rigid_bodies": [)" + ground + R"(], "fem_bodies": [{)" + block +
                         R"(, "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 1e5,
                             "poisson_ratio": 0.3}], "solver": {}}]})",
                     "fem_bodies[0].solver");
  expect_scene_error(R"({"rigid_bodies": [)" + ground + R"(], "dynamics": {"time_step": 0.01, "steps": 1},
                         "fem_bodies": [{)" +
                         block +
                         R"(, "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 1e5,
                             "poisson_ratio": 0.3}]}]})",
                     "static scenes only");
  // A block that starts inside the ground.
  expect_scene_error(R"({"rigid_bodies": [)" + ground +
                         R"(], "fem_bodies": [{"mesh": {"box": {"min": [0, 0, -0.1], "max": [1, 1, 1],
                         "cells": [1, 1, 1]}}, "materials": [{"elements": "all", "model": "linear",
                         "youngs_modulus": 1e5, "poisson_ratio": 0.3}]}]})",
                     "touch or intersect");
}

}  // namespace
}  // namespace tailor::fem_contact_scene_test
