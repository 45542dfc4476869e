// Validation of the meshless solid (docs/meshless.md, "Validation"):
//  - the patch test first: a cube whose boundary nodes are held, by the transformation method,
//    at an affine map; the solved interior reproduces it up to the quadrature's consistency
//    error, which falls with the Gauss order (EFG with Gauss cells is not integrated exactly);
//  - a cantilever 10 x 1 x 1 clamped at x = 0 under a unit end shear, against Timoshenko beam
//    theory, w = F L^3 / (3 E I) + F L / (kappa G A), kappa = 5/6, as the nodes are refined, next
//    to tailor's linear tets on the same box.
// The tables are printed; docs/meshless.md quotes them.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/meshless/covering_patches.hpp"
#include "forward/meshless/essential_conditions.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "meshless_fixtures.hpp"

namespace tailor::meshless_validation_test {
namespace {

using namespace tailor::meshless_testing;

Model meshless_model(const MeshlessSolid& s) {
  Model model(3 * s.num_nodes());
  model.parameter_layout().add("youngs_modulus", s.num_nodes());
  model.parameter_layout().add("poisson_ratio", s.num_nodes());
  model.add(std::make_unique<MeshlessElasticTerm<3>>(s.quadrature, make_material<3>(MaterialKind::linear), 0,
                                                     s.num_nodes()));
  return model;
}

// ---------------------------------------------------------------------------------------------
// Patch test: the uniform stress of x(X) = A X + c (linear material). The face x = 0 is held at
// the affine map by the transformation method (its collocation points), and the other faces,
// and x = 0 between its collocation points, carry the matching tractions P n by a Gauss rule of
// the same order as the volume's. The affine coefficients then satisfy the discrete equations
// up to the quadrature's consistency error (sum_q w_q P grad phi_a against the boundary
// integral of phi_a P n), which falls with the Gauss order: EFG with Gauss cells does not
// integrate its rational shape functions exactly.
constexpr double kPatchSpacing = 0.25;

// Gauss points of the boundary of the unit cube: cells of edge h on each face, `order` points per
// axis, with the outward normal.
void cube_boundary_rule(double h, int order, Eigen::MatrixXd& points, Eigen::VectorXd& weights,
                        Eigen::MatrixXd& normals) {
  std::vector<double> gx, gw;
  gauss_legendre(order, gx, gw);
  const int cells = static_cast<int>(std::lround(1.0 / h));
  const int per_face = cells * cells * order * order;
  points.resize(6 * per_face, 3);
  weights.resize(6 * per_face);
  normals.resize(6 * per_face, 3);
  int k = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int ci = 0; ci < cells; ++ci)
        for (int cj = 0; cj < cells; ++cj)
          for (std::size_t a = 0; a < gx.size(); ++a)
            for (std::size_t b = 0; b < gx.size(); ++b, ++k) {
              Eigen::Vector3d X;
              X[axis] = side;
              X[(axis + 1) % 3] = h * (ci + 0.5 * (1 + gx[a]));
              X[(axis + 2) % 3] = h * (cj + 0.5 * (1 + gx[b]));
              points.row(k) = X.transpose();
              weights[k] = 0.25 * h * h * gw[a] * gw[b];
              normals.row(k) = (side == 0 ? -1.0 : 1.0) * Eigen::RowVector3d::Unit(axis);
            }
}

// with_tractions = false: the whole boundary held at the affine map by the transformation
// method and no traction, the variant that does not pass (see the test).
// covered: patches grown by cover_points where a volume or boundary point is not covered
// (covering_patches.hpp), from each node's neighbours-th nearest node (neighbours > 0) or the
// lattice spacing.
double patch_error(int quadrature_order, bool with_tractions = true, double support_factor = 2.0, bool covered = false,
                   int neighbours = 0) {
  MlsOptions mls_options;
  mls_options.support_factor = support_factor;
  MeshlessSolid s = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), kPatchSpacing,
                               quadrature_order, 0, covered ? MlsOptions{} : mls_options);
  Eigen::MatrixXd points, normals;
  Eigen::VectorXd weights;
  cube_boundary_rule(kPatchSpacing, quadrature_order, points, weights, normals);
  if (covered) {
    Eigen::MatrixXd all(s.sampling.points.rows() + points.rows(), 3);
    all << s.sampling.points, points;
    const Eigen::VectorXd initial = neighbours > 0 ? neighbour_spacing(s.sampling.nodes, neighbours) : s.sampling.spacing;
    const Eigen::VectorXd spacing = cover_points(s.sampling.nodes, initial, all, mls_options);
    s.mls = std::make_shared<MlsShapeFunctions>(s.sampling.nodes, spacing, mls_options);
    s.quadrature = std::make_shared<MeshlessQuadrature>(
        build_meshless_quadrature(*s.mls, s.sampling.points, s.sampling.weights));
  }
  Eigen::Matrix3d A;
  A << 1.01, 0.002, -0.003, 0.001, 0.995, 0.004, -0.002, 0.003, 1.006;
  const Eigen::Vector3d c(0.01, -0.02, 0.005);
  const double E = 1000.0, nu = 0.3;
  // The linear material's stress at F = A.
  MaterialEvaluation<3> m;
  make_material<3>(MaterialKind::linear)->evaluate(A, lame_from_young_poisson(E, nu), true, false, HessianMode::exact, m);
  const Eigen::MatrixXd tractions = normals * m.stress.transpose();  // row s: (P n_s)^T
  std::vector<int> held;
  for (int a = 0; a < s.num_nodes(); ++a) {
    const Eigen::Vector3d X = s.sampling.nodes.row(a).transpose();
    if (with_tractions ? X[0] < 1e-9 : ((X.array() < 1e-9).any() || (X.array() > 1 - 1e-9).any())) held.push_back(a);
  }
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(held.size()), 3);
  for (std::size_t i = 0; i < held.size(); ++i)
    targets.row(static_cast<Eigen::Index>(i)) = (A * s.sampling.nodes.row(held[i]).transpose() + c).transpose();
  Model model = meshless_model(s);
  if (with_tractions)
    model.add(std::make_unique<ExternalForceTerm>(meshless_point_forces(*s.mls, points, weights, tractions)));
  model.set_elimination(mls_transformation(*s.mls, held, targets).elimination);
  const Vector x = solve_equilibrium(model, uniform_parameters(s.num_nodes(), E, nu), s.rest());
  // Largest deviation of F_q from A over the quadrature points, relative to |A - I|.
  double error = 0.0;
  for (int q = 0; q < s.quadrature->num_points(); ++q)
    error = std::max(error, (s.quadrature->deformation_gradient(x, q) - A).norm());
  return error / (A - Eigen::Matrix3d::Identity()).norm();
}

TEST(MeshlessValidation, PatchTestUniformStressReproducedToQuadratureAccuracy) {
  std::printf("patch test, unit cube, h = 0.25, uniform stress by tractions, x = 0 held\n%6s %24s\n", "Gauss",
              "max_q |F_q - A| / |A - I|");
  std::vector<double> errors;
  for (int order : {1, 2, 3, 4}) {
    errors.push_back(patch_error(order));
    std::printf("%6d %24.3e\n", order, errors.back());
  }
  // One point per cell is rank-deficient (the solution is far off); from two points per axis the
  // error falls with the order: measured 2.4e-3, 1.2e-3, 3.6e-5 at orders 2, 3, 4.
  EXPECT_GT(errors[0], 1.0);
  EXPECT_LT(errors[1], 1e-2);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[3], errors[2]);
  EXPECT_LT(errors[3], 1e-4);
  // Every boundary node held at the affine map, no traction: between the collocation points the
  // boundary is traction-free in the weak form, which the affine field does not satisfy, so the
  // error stays at the percent level whatever the quadrature.
  const double held_only = patch_error(2, false);
  std::printf("boundary nodes held, no tractions, 2 Gauss points: %.3e\n", held_only);
  EXPECT_GT(held_only, 1e-3);
  // A smaller support (fewer couplings, a cheaper Newton step: docs/meshless.md, "Bench") passes
  // to the same level; its quadrature error is not monotone in the Gauss order (measured at
  // R = 1.5h: 9.2e-4 and 3.9e-4 with 2 and 4 points per axis; at R = 1.25h: 3.5e-5 and 3.0e-3).
  for (const double support_factor : {1.5, 1.25}) {
    const double order2 = patch_error(2, true, support_factor), order4 = patch_error(4, true, support_factor);
    std::printf("R = %.2f h: %.3e (2 Gauss points), %.3e (4)\n", support_factor, order2, order4);
    EXPECT_LT(order2, 1e-2);
    EXPECT_LT(order4, 1e-2);
  }
  // R = 1.2h, grown by cover_points where a point (of the volume or of the boundary rule) is not
  // covered: the one-layer coupling of the fast Newton step (docs/meshless.md, "Bench"). With 2
  // Gauss points per axis and no growth needed the affine field is reproduced to round-off
  // (measured 5.0e-13); with 3, the face centres' points see only coplanar face nodes and the
  // grown patches leave a quadrature error of 9.2e-3. Patches from each node's sixth neighbour
  // (1.2h inside, 1.2 sqrt(2) h on the boundary) pass with 3 points (6.5e-3) but not with 2
  // (0.25): supports of two sizes meeting inside the cells break the 2-point rule's consistency,
  // which is why the bench's fast option keeps the lattice spacing.
  std::vector<double> covered;
  for (const int neighbours : {0, 6})
    for (const int order : {2, 3}) {
      covered.push_back(patch_error(order, true, 1.2, true, neighbours));
      std::printf("R = 1.2 x %s, covered: %.3e (%d Gauss points)\n", neighbours ? "sixth-neighbour distance" : "h",
                  covered.back(), order);
    }
  EXPECT_LT(covered[0], 1e-10);
  EXPECT_LT(covered[1], 1e-2);
  EXPECT_GT(covered[2], 0.1);
  EXPECT_LT(covered[3], 1e-2);
}

// ---------------------------------------------------------------------------------------------
// Cantilever: [0, 10] x [0, 1] x [0, 1], clamped at x = 0, traction (0, 0, -1) on x = 10.
constexpr double kLength = 10.0, kModulus = 1000.0, kPoisson = 0.3, kForce = 1.0;

double timoshenko_deflection() {
  const double I = 1.0 / 12.0, A = 1.0, G = kModulus / (2 * (1 + kPoisson)), kappa = 5.0 / 6.0;
  return kForce * std::pow(kLength, 3) / (3 * kModulus * I) + kForce * kLength / (kappa * G * A);
}

// The end face's Gauss points (cells of edge h, 2 x 2 points each), traction (0, 0, -1).
void end_face_rule(double h, Eigen::MatrixXd& points, Eigen::VectorXd& weights, Eigen::MatrixXd& densities) {
  std::vector<double> gx, gw;
  gauss_legendre(2, gx, gw);
  const int cells = static_cast<int>(std::lround(1.0 / h));
  points.resize(4 * cells * cells, 3);
  weights.resize(4 * cells * cells);
  densities.resize(4 * cells * cells, 3);
  int k = 0;
  for (int ci = 0; ci < cells; ++ci)
    for (int cj = 0; cj < cells; ++cj)
      for (std::size_t a = 0; a < 2; ++a)
        for (std::size_t b = 0; b < 2; ++b, ++k) {
          points.row(k) << kLength, h * (ci + 0.5 * (1 + gx[a])), h * (cj + 0.5 * (1 + gx[b]));
          weights[k] = 0.25 * h * h * gw[a] * gw[b];
          densities.row(k) << 0, 0, -kForce;
        }
}

struct BeamResult {
  int nodes;
  double deflection;  // f . u / F: the load-weighted mean deflection of the end face
};

BeamResult meshless_beam(double h, int order) {
  const MeshlessSolid s = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(kLength, 1, 1)), h, order, 0);
  Eigen::MatrixXd points, densities;
  Eigen::VectorXd weights;
  end_face_rule(h, points, weights, densities);
  const Vector f = meshless_point_forces(*s.mls, points, weights, densities);
  std::vector<int> clamped;
  for (int a = 0; a < s.num_nodes(); ++a)
    if (s.sampling.nodes(a, 0) < 1e-9) clamped.push_back(a);
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(clamped.size()), 3);
  for (std::size_t i = 0; i < clamped.size(); ++i) targets.row(static_cast<Eigen::Index>(i)) = s.sampling.nodes.row(clamped[i]);
  Model model = meshless_model(s);
  model.add(std::make_unique<ExternalForceTerm>(f));
  model.set_elimination(mls_transformation(*s.mls, clamped, targets).elimination);
  const Vector rest = s.rest();
  const Vector x = solve_equilibrium(model, uniform_parameters(s.num_nodes(), kModulus, kPoisson), rest);
  return {s.num_nodes(), f.dot(x - rest) / kForce};
}

BeamResult fem_beam(int per_unit) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(kLength, 1, 1),
                                 static_cast<int>(kLength) * per_unit, per_unit, per_unit);
  const int m = mesh.num_elements(), n = mesh.num_vertices();
  Model model(3 * n);
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::linear), 0, m));
  const Eigen::MatrixXi end = boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[0] > kLength - 1e-9; });
  const Vector f = traction_forces(mesh, end, Eigen::Vector3d(0, 0, -kForce));
  model.add(std::make_unique<ExternalForceTerm>(f));
  const Eigen::MatrixXd t = mesh.rest_positions.transpose();
  const Vector rest = Eigen::Map<const Vector>(t.data(), t.size());
  std::vector<int> fixed;
  for (int v = 0; v < n; ++v)
    if (mesh.rest_positions(v, 0) < 1e-9)
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
  model.set_elimination(Elimination::dirichlet(fixed, rest));
  Vector p(2 * m);
  p.head(m).setConstant(kModulus);
  p.tail(m).setConstant(kPoisson);
  const Vector x = solve_equilibrium(model, p, rest);
  return {n, f.dot(x - rest) / kForce};
}

TEST(MeshlessValidation, CantileverAgainstTimoshenkoAndLinearTets) {
  const double exact = timoshenko_deflection();
  std::printf("cantilever 10 x 1 x 1, E = 1000, nu = 0.3, end shear F = 1: Timoshenko w = %.5f\n", exact);
  std::printf("%-22s %7s %12s %10s %7s\n", "method", "nodes", "deflection", "rel. error", "rate");
  std::vector<double> errors;
  std::vector<double> spacings = {0.5, 1.0 / 3.0, 0.25};
  for (double h : spacings) {
    const auto start = std::chrono::steady_clock::now();
    const BeamResult r = meshless_beam(h, 3);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double error = std::abs(r.deflection - exact) / exact;
    const double rate = errors.empty() ? NAN
                                       : std::log(errors.back() / error) /
                                             std::log(spacings[errors.size() - 1] / h);
    std::printf("meshless h = %-10.4f %7d %12.6f %10.3e %7.2f   (%.1f s: sampling, MLS, solve)\n", h, r.nodes,
                r.deflection, error, rate, seconds);
    errors.push_back(error);
  }
  std::vector<double> fem_errors;
  for (int per_unit : {2, 3, 4}) {
    const BeamResult r = fem_beam(per_unit);
    fem_errors.push_back(std::abs(r.deflection - exact) / exact);
    std::printf("P1 tets h = %-11.4f %7d %12.6f %10.3e\n", 1.0 / per_unit, r.nodes, r.deflection, fem_errors.back());
  }
  // The meshless solution approaches beam theory as the nodes are refined and is within 2% at
  // h = 1/4; the linear tets on the same nodes lock in bending and stay further off.
  EXPECT_LT(errors.back(), errors.front());
  EXPECT_LT(errors.back(), 0.02);
  EXPECT_LT(errors.back(), fem_errors.back());
}

}  // namespace
}  // namespace tailor::meshless_validation_test
