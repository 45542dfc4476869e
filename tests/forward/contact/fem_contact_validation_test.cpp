// ContactTerm on FEM boundary triangles in a Newton solve: an elastic cube resting under
// gravity on a fixed floor. Reference (statics): the floor's total contact force on the cube
// equals the cube's weight rho V g, and the cube never touches the floor (distance > 0).
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "forward/contact/contact_term.hpp"
#include "forward/dynamics/gravity_term.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::fem_contact_validation_test {
namespace {

void solve_cube_on_floor(double pattern_distance) {
  const double side = 0.2, density = 1000.0, g = 9.81, d_hat = 1e-3;
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(-0.1, -0.1, 0.5 * d_hat),
                           Eigen::Vector3d(0.1, 0.1, side + 0.5 * d_hat), 3, 3, 3);
  const int cube_vertices = mesh.num_vertices();
  // The floor: four extra vertices (no elements) at z = 0.
  mesh.rest_positions.conservativeResize(cube_vertices + 4, 3);
  mesh.rest_positions.bottomRows(4) << -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0;
  const int n = 3 * mesh.num_vertices();
  Vector rest(n);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    rest.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();

  // Contact surface: the cube's boundary triangles and the floor's two triangles.
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  std::set<int> on_surface(facets.data(), facets.data() + facets.size());
  for (int v = cube_vertices; v < cube_vertices + 4; ++v) on_surface.insert(v);
  std::vector<int> surface_vertex(static_cast<std::size_t>(mesh.num_vertices()), -1), dofs;
  for (int v : on_surface) {
    surface_vertex[static_cast<std::size_t>(v)] = static_cast<int>(dofs.size());
    dofs.push_back(3 * v);
  }
  Eigen::MatrixX3i faces(facets.rows() + 2, 3);
  for (int f = 0; f < facets.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces(f, k) = surface_vertex[static_cast<std::size_t>(facets(f, k))];
  const int c0 = cube_vertices;
  auto s = [&](int v) { return surface_vertex[static_cast<std::size_t>(v)]; };
  faces.row(facets.rows()) << s(c0), s(c0 + 1), s(c0 + 2);
  faces.row(facets.rows() + 1) << s(c0), s(c0 + 2), s(c0 + 3);

  Model model(n);
  const int m = mesh.num_elements();
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.parameter_layout().add("density", m);
  Vector p(3 * m);
  p << Vector::Constant(m, 1e5), Vector::Constant(m, 0.3), Vector::Constant(m, density);
  model.add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m));
  model.add(std::make_unique<GravityTerm>(mesh, Eigen::Vector3d(0, 0, -g), 2 * m));
  contact::ContactOptions options;
  options.activation_distance = d_hat;
  options.stiffness = 1e8;
  const ContactTerm& contact = model.add(
      std::make_unique<ContactTerm>(contact::ContactSurface::from_faces(static_cast<int>(dofs.size()), faces),
                                    dofs, rest, options, pattern_distance));
  // Fixed: the floor; the lateral position and spin of the frictionless cube (x, y of the
  // first vertex, y of a vertex on the same bottom edge).
  std::vector<int> fixed;
  for (int k = 3 * cube_vertices; k < n; ++k) fixed.push_back(k);
  fixed.push_back(0);
  fixed.push_back(1);
  fixed.push_back(3 * 1 + 1);
  model.set_elimination(Elimination::dirichlet(fixed, rest));

  NewtonSolver newton(model);
  Vector y = model.elimination().restrict_state(rest);
  const NewtonResult result = newton.solve(p, y);
  ASSERT_TRUE(result.converged()) << result.report();
  const Vector x = model.state(y, p);
  Vector gradient = Vector::Zero(n);
  contact.add_gradient(x, p, gradient);
  double on_cube = 0.0, on_floor = 0.0;
  for (int v = 0; v < cube_vertices; ++v) on_cube -= gradient[3 * v + 2];
  for (int v = cube_vertices; v < mesh.num_vertices(); ++v) on_floor -= gradient[3 * v + 2];
  const double weight = density * side * side * side * g;
  const double gap = contact.potential().min_distance(contact.positions(x), 1.0);
  std::printf(
      "FEM cube on floor (pattern %s): %d Newton iterations, contact force %.10g N, weight %.10g N, "
      "%d active pairs, min distance %.3g m\n",
      std::isinf(pattern_distance) ? "dense" : "candidates", result.iterations, on_cube, weight,
      contact.potential().num_active(contact.positions(x)), gap);
  EXPECT_NEAR(on_cube, weight, 1e-6 * weight);
  EXPECT_NEAR(on_floor, -weight, 1e-6 * weight);
  EXPECT_GT(gap, 0.0);
  EXPECT_LT(gap, d_hat);
}

TEST(FemContactValidation, ElasticCubeOnFloorCarriesItsWeightDensePattern) {
  solve_cube_on_floor(std::numeric_limits<double>::infinity());
}

TEST(FemContactValidation, ElasticCubeOnFloorCarriesItsWeightCandidatePattern) { solve_cube_on_floor(0.01); }

}  // namespace
}  // namespace tailor::fem_contact_validation_test
