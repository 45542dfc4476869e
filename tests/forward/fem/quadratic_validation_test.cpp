// Validation of the quadratic (P2) elements against closed forms and published values, next to
// the linear (P1) ones, for nearly incompressible linear elasticity (nu = 0.4999) where linear
// simplices lock:
//  - the pressurized thick cylinder (Lame), plane strain on triangles and on a one-layer slab of
//    tets with u_z = 0: P2 converges to the closed-form radial displacement, P1 stays far off;
//  - Cook's membrane: P2 against a published converged tip deflection of the compressible
//    benchmark, and P2 against P1 at nu = 0.4999.
// The tables are printed (ctest --output-on-failure -V); docs/materials.md quotes them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/core/elimination.hpp"
#include "forward/core/model.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/fem/quadratic_elastic_term.hpp"
#include "forward/fem/quadratic_loads.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/solve/newton.hpp"
#include "../../support/equilibrium.hpp"

namespace tailor::quadratic_validation_test {
namespace {

// Parameters [E per element, nu per element].
Vector uniform_parameters(int elements, double youngs_modulus, double poisson_ratio) {
  Vector p(2 * elements);
  p.head(elements).setConstant(youngs_modulus);
  p.tail(elements).setConstant(poisson_ratio);
  return p;
}

Vector flat_positions(const Eigen::MatrixXd& positions) {
  const Eigen::MatrixXd t = positions.transpose();
  return Eigen::Map<const Vector>(t.data(), t.size());
}

// The equilibrium of `model` (linear material: one Newton step, checked to converge).
using tailor::testing::solve_equilibrium;

// Consistent nodal forces of a uniform pressure on straight linear boundary edges (2D): half of
// -p n l to each end.
Vector linear_pressure_forces(const Mesh& mesh, const Eigen::MatrixXi& facets, double pressure) {
  Vector f = Vector::Zero(2 * mesh.num_vertices());
  for (int k = 0; k < facets.rows(); ++k) {
    const Eigen::Vector2d t = (mesh.rest_positions.row(facets(k, 1)) - mesh.rest_positions.row(facets(k, 0))).transpose();
    const Eigen::Vector2d normal_length(t[1], -t[0]);  // outward for boundary_facets' orientation
    for (int a = 0; a < 2; ++a) f.segment<2>(2 * facets(k, a)) -= 0.5 * pressure * normal_length;
  }
  return f;
}

// ---------------------------------------------------------------------------------------------
// Thick cylinder, inner radius a, outer radius b, internal pressure q, plane strain (Timoshenko &
// Goodier, Theory of Elasticity, 3rd ed., section 28; plane strain form, e.g. Barber,
// Elasticity, section 8.3.1):  u_r(r) = (1 + nu) q a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r).
// A quarter of it, with symmetry conditions on x = 0 and y = 0.
constexpr double kInner = 1.0, kOuter = 2.0, kPressure = 1.0, kModulus = 1000.0, kPoisson = 0.4999;

// Linear triangles of the linear material, per-element E and nu in p (the P1 comparisons).
Model linear_plane_model(const Mesh& mesh) {
  const int m = mesh.num_elements();
  Model model(2 * mesh.num_vertices());
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<ElasticTerm<2>>(mesh, make_material<2>(MaterialKind::linear), 0, m));
  return model;
}

double lame_radial_displacement(double r) {
  return (1 + kPoisson) * kPressure * kInner * kInner / (kModulus * (kOuter * kOuter - kInner * kInner)) *
         ((1 - 2 * kPoisson) * r + kOuter * kOuter / r);
}

// (r, theta[, z]) -> (r cos theta, r sin theta[, z]): orientation-preserving (Jacobian r > 0).
void to_polar(Eigen::MatrixXd& positions) {
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    const double r = positions(v, 0), theta = positions(v, 1);
    positions(v, 0) = r * std::cos(theta);
    positions(v, 1) = r * std::sin(theta);
  }
}

bool on_inner(const Eigen::VectorXd& X) { return std::hypot(X[0], X[1]) < kInner + 1e-9; }

// Symmetry (u_x = 0 on x = 0, u_y = 0 on y = 0) and, in 3D, u_z = 0 everywhere (plane strain).
std::vector<int> cylinder_fixed_dofs(const Eigen::MatrixXd& positions) {
  const int dim = static_cast<int>(positions.cols());
  std::vector<int> fixed;
  for (int v = 0; v < positions.rows(); ++v) {
    if (std::abs(positions(v, 0)) < 1e-9) fixed.push_back(dim * v);
    if (std::abs(positions(v, 1)) < 1e-9) fixed.push_back(dim * v + 1);
    if (dim == 3) fixed.push_back(dim * v + 2);
  }
  return fixed;
}

// max over nodes |u_r - u_r(exact)| / u_r(exact, a), and |u_theta| in the same scale.
double cylinder_error(const Eigen::MatrixXd& positions, const Vector& x) {
  const int dim = static_cast<int>(positions.cols());
  double error = 0.0;
  for (int v = 0; v < positions.rows(); ++v) {
    const Eigen::Vector2d X = positions.row(v).head<2>().transpose();
    const Eigen::Vector2d u = x.segment<2>(dim * v) - X;
    const double r = X.norm();
    const Eigen::Vector2d er = X / r, et(-er[1], er[0]);
    error = std::max({error, std::abs(u.dot(er) - lame_radial_displacement(r)), std::abs(u.dot(et))});
  }
  return error / lame_radial_displacement(kInner);
}

double cylinder_p1_error(int nr, int nt) {
  Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(kInner, 0), Eigen::Vector2d(kOuter, M_PI / 2), nr, nt);
  to_polar(mesh.rest_positions);
  Model model = linear_plane_model(mesh);
  const int m = mesh.num_elements();
  model.add(std::make_unique<ExternalForceTerm>(
      linear_pressure_forces(mesh, boundary_facets_where(mesh, on_inner), kPressure)));
  const Vector rest = flat_positions(mesh.rest_positions);
  model.set_elimination(Elimination::dirichlet(cylinder_fixed_dofs(mesh.rest_positions), rest));
  return cylinder_error(mesh.rest_positions, solve_equilibrium(model, uniform_parameters(m, kModulus, kPoisson), rest));
}

// Quadratic: every node (edge nodes included) mapped to the annulus, so the curved boundary is
// represented to third order.
template <int Dim>
double cylinder_p2_error(int nr, int nt) {
  Mesh param = Dim == 2 ? rectangle_triangle_mesh(Eigen::Vector2d(kInner, 0), Eigen::Vector2d(kOuter, M_PI / 2), nr, nt)
                        : box_tet_mesh(Eigen::Vector3d(kInner, 0, 0), Eigen::Vector3d(kOuter, M_PI / 2, 0.25), nr, nt, 1);
  QuadraticMesh q = make_quadratic_mesh(param);
  to_polar(q.rest_positions);
  to_polar(q.corners.rest_positions);
  Model model(Dim * q.num_nodes());
  const int m = q.num_elements();
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<QuadraticElasticTerm<Dim>>(q, make_material<Dim>(MaterialKind::linear), 0, m));
  const Eigen::MatrixXi inner = quadratic_facets(q, boundary_facets_where(q.corners, on_inner));
  model.add(std::make_unique<ExternalForceTerm>(quadratic_pressure_forces(q, inner, kPressure)));
  const Vector rest = quadratic_rest_state(q);
  model.set_elimination(Elimination::dirichlet(cylinder_fixed_dofs(q.rest_positions), rest));
  return cylinder_error(q.rest_positions, solve_equilibrium(model, uniform_parameters(m, kModulus, kPoisson), rest));
}

TEST(ThickCylinder, QuadraticTrianglesConvergeWhereLinearOnesLock) {
  std::printf("thick cylinder, plane strain, nu = %.4f: max nodal error / u_r(a)\n  cells      P1        P2\n", kPoisson);
  double previous = 1.0;
  for (int n : {2, 4, 8}) {
    const double p1 = cylinder_p1_error(n, 2 * n), p2 = cylinder_p2_error<2>(n, 2 * n);
    std::printf("  %2d x %2d  %.3e  %.3e\n", n, 2 * n, p1, p2);
    EXPECT_GT(p1, 0.3) << "linear triangles should lock at nu = 0.4999";
    EXPECT_LT(p2, 0.5 * previous) << "quadratic triangles must converge";
    previous = p2;
  }
  EXPECT_LT(previous, 5e-3);
}

TEST(ThickCylinder, QuadraticTetsConverge) {
  std::printf("thick cylinder, one-layer tet slab with u_z = 0, nu = %.4f: max nodal error / u_r(a)\n", kPoisson);
  double previous = 1.0;
  for (int n : {2, 4, 8}) {
    const double p2 = cylinder_p2_error<3>(n, 2 * n);
    std::printf("  %2d x %2d x 1  P2 %.3e\n", n, 2 * n, p2);
    EXPECT_LT(p2, 0.7 * previous) << "quadratic tets must converge";
    previous = p2;
  }
  EXPECT_LT(previous, 2e-2);
}

// ---------------------------------------------------------------------------------------------
// Cook's membrane (Cook 1974): the trapezoid with corners (0,0), (48,44), (48,60), (0,44),
// clamped on x = 0, a uniform vertical shear traction of total F on x = 48; the quantity is the
// vertical displacement of the top right corner C = (48, 60).

// The bilinear map of the unit square onto the membrane (straight cell edges on the boundary).
Eigen::Vector2d cook_point(double s, double t) {
  const Eigen::Vector2d A(0, 0), B(48, 44), C(48, 60), D(0, 44);
  return (1 - s) * (1 - t) * A + s * (1 - t) * B + s * t * C + (1 - s) * t * D;
}

void to_cook(Eigen::MatrixXd& positions) {
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    positions.row(v) = cook_point(positions(v, 0), positions(v, 1)).transpose();
}

int node_at(const Eigen::MatrixXd& positions, const Eigen::Vector2d& X) {
  for (int v = 0; v < positions.rows(); ++v)
    if ((positions.row(v).transpose() - X).norm() < 1e-9) return v;
  ADD_FAILURE() << "no node at (" << X.transpose() << ")";
  return 0;
}

bool on_left(const Eigen::VectorXd& X) { return X[0] < 1e-9; }
bool on_right(const Eigen::VectorXd& X) { return X[0] > 48 - 1e-9; }

double cook_tip_p1(int n, double E, double nu, double F) {
  Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), n, n);
  to_cook(mesh.rest_positions);
  Model model = linear_plane_model(mesh);
  const int m = mesh.num_elements();
  model.add(std::make_unique<ExternalForceTerm>(
      traction_forces(mesh, boundary_facets_where(mesh, on_right), Eigen::Vector2d(0, F / 16))));
  std::vector<int> fixed;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (on_left(mesh.rest_positions.row(v).transpose())) fixed.insert(fixed.end(), {2 * v, 2 * v + 1});
  const Vector rest = flat_positions(mesh.rest_positions);
  model.set_elimination(Elimination::dirichlet(fixed, rest));
  const Vector x = solve_equilibrium(model, uniform_parameters(m, E, nu), rest);
  const int c = node_at(mesh.rest_positions, Eigen::Vector2d(48, 60));
  return x[2 * c + 1] - rest[2 * c + 1];
}

double cook_tip_p2(int n, double E, double nu, double F) {
  QuadraticMesh q = make_quadratic_mesh(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), n, n));
  to_cook(q.rest_positions);
  to_cook(q.corners.rest_positions);
  Model model(2 * q.num_nodes());
  const int m = q.num_elements();
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<QuadraticElasticTerm<2>>(q, make_material<2>(MaterialKind::linear), 0, m));
  const Eigen::MatrixXi right = quadratic_facets(q, boundary_facets_where(q.corners, on_right));
  model.add(std::make_unique<ExternalForceTerm>(quadratic_traction_forces(q, right, Eigen::Vector2d(0, F / 16))));
  const Vector rest = quadratic_rest_state(q);
  // The clamp holds the edge nodes of x = 0 too.
  model.set_elimination(Elimination::dirichlet(node_dofs(q, nodes_where(q, on_left)), rest));
  const Vector x = solve_equilibrium(model, uniform_parameters(m, E, nu), rest);
  const int c = node_at(q.rest_positions, Eigen::Vector2d(48, 60));
  return x[2 * c + 1] - rest[2 * c + 1];
}

// The compressible benchmark with a published converged value: plane strain, E = 70, nu = 1/3,
// shear traction 6.25 on the 16 long edge (F = 100); converged u_y(C) = 32.27 (CalculiX, 32.28
// Elmer, 32.20 Code_Aster, very fine quadratic meshes), as tabulated from CoFEA in the solids4foam
// tutorial "Linear Elastic Cook's Membrane"
// (https://www.solids4foam.com/tutorials/more-tutorials/solid-mechanics/linearElasticity/cooksMembrane.html,
// geometry, E, nu and traction checked there). The page solves it in 2D without naming the
// plane condition; plane stress would give 35.9 here, plane strain gives the tabulated value, so
// it is plane strain. (The plane-stress variant E = 1, nu = 1/3, F = 1 with the value 23.96 quoted
// from Cook et al. 1989 elsewhere did not reproduce: P1 and P2 both converge to 25.15 on 64 x 64
// cells, so its setup must differ from what we could read, and we do not assert it.)
TEST(CooksMembrane, QuadraticTrianglesMatchThePublishedValue) {
  const double E = 70.0, nu = 1.0 / 3.0, F = 100.0, reference = 32.27;
  std::printf("Cook's membrane, plane strain E = 70, nu = 1/3, F = 100 (reference 32.27): u_y(C)\n  cells    P1       P2\n");
  double p2 = 0.0;
  for (int n : {4, 8, 16, 32}) {
    const double p1 = cook_tip_p1(n, E, nu, F);
    p2 = cook_tip_p2(n, E, nu, F);
    std::printf("  %2d x %2d  %.4f  %.4f\n", n, n, p1, p2);
  }
  EXPECT_NEAR(p2, reference, 0.005 * reference);
}

// Nearly incompressible, plane strain, E = 1, nu = 0.4999, F = 1 (the usual variant of the
// benchmark for volumetric locking). We could not verify a published converged value for this
// setup (the searches found the compressible ones above and elastoplastic variants), so the test
// compares the meshes with each other: P2 settles (successive changes shrink, the finest two
// agree to 2%: the singular corner at (0, 44) slows it), and P1 on the same meshes locks, at
// less than a third of it.
TEST(CooksMembrane, NearlyIncompressibleQuadraticTrianglesDoNotLock) {
  const double E = 1.0, nu = 0.4999, F = 1.0;
  std::printf("Cook's membrane, plane strain E = 1, nu = 0.4999, F = 1: u_y(C)\n  cells    P1       P2\n");
  std::vector<double> p1, p2;
  for (int n : {4, 8, 16, 32}) {
    p1.push_back(cook_tip_p1(n, E, nu, F));
    p2.push_back(cook_tip_p2(n, E, nu, F));
    std::printf("  %2d x %2d  %.4f  %.4f\n", n, n, p1.back(), p2.back());
  }
  EXPECT_LT(std::abs(p2[3] - p2[2]), std::abs(p2[2] - p2[1]));
  EXPECT_LT(std::abs(p2[3] - p2[2]), 0.02 * p2[3]);
  EXPECT_LT(p1[3], 0.35 * p2[3]) << "linear triangles should lock";
}

}  // namespace
}  // namespace tailor::quadratic_validation_test
