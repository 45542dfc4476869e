// Validation against beam theory (not against anything written here): the tip deflection of
// a clamped cantilever under an end shear load P,
//   delta = P L^3 / (3 E I) + P L / (kappa G A)        (Timoshenko: bending + shear),
// with kappa = 5/6 for a rectangular section, G = E / (2 (1 + nu)). With nu = 0 the 3D and
// plane-strain solutions have no Poisson coupling at the clamp, so the remaining difference
// to beam theory is the discretisation error of linear simplices (which lock in bending and
// converge from below at second order in the mesh size).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::cantilever_test {
namespace {

using namespace tailor::testing;

constexpr double kLength = 10.0, kHeight = 1.0, kYoung = 1000.0, kLoad = 1.0;

double beam_theory_deflection(double width) {
  const double I = width * kHeight * kHeight * kHeight / 12.0, A = width * kHeight, G = kYoung / 2.0;
  return kLoad * kLength * kLength * kLength / (3.0 * kYoung * I) + kLoad * kLength / (5.0 / 6.0 * G * A);
}

// Mean deflection (along the last axis) of the loaded end face, for n elements through the
// height.
template <int Dim>
double fem_tip_deflection(int n) {
  const Mesh mesh = Dim == 3 ? box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(kLength, kHeight, kHeight),
                                            10 * n, n, n)
                             : rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(kLength, kHeight), 10 * n, n);
  const int m = mesh.num_elements();
  Model model(Dim * mesh.num_vertices());
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(elastic_term<Dim>(mesh, MaterialKind::linear));

  // Uniform shear traction on the end face x = L with resultant P (width 1 in both cases).
  const Eigen::MatrixXi end_facets =
      boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[0] > kLength - 1e-9; });
  Eigen::VectorXd traction = Eigen::VectorXd::Zero(Dim);
  traction[Dim - 1] = -kLoad / kHeight / (Dim == 3 ? kHeight : 1.0);
  model.add(std::make_unique<ExternalForceTerm>(traction_forces(mesh, end_facets, traction)));

  std::vector<int> clamped;
  std::vector<int> tip;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.rest_positions(v, 0) < 1e-9)
      for (int k = 0; k < Dim; ++k) clamped.push_back(Dim * v + k);
    if (mesh.rest_positions(v, 0) > kLength - 1e-9) tip.push_back(v);
  }
  const Vector rest = rest_state(mesh);
  model.set_elimination(Elimination::dirichlet(clamped, rest));
  Vector p(2 * m);
  p.head(m).setConstant(kYoung);
  p.tail(m).setConstant(0.0);

  NewtonSolver solver(model);
  Vector y = model.elimination().restrict_state(rest);
  const NewtonResult r = solver.solve(p, y);
  EXPECT_TRUE(r.converged()) << r.report();
  const Vector x = model.elimination().expand(y);
  double sum = 0.0;
  for (int v : tip) sum += x[Dim * v + Dim - 1] - rest[Dim * v + Dim - 1];
  return -sum / static_cast<double>(tip.size());
}

template <int Dim>
void expect_convergence(const std::vector<int>& refinements, double max_final_error, double min_rate) {
  const double reference = beam_theory_deflection(1.0);
  std::printf("%dD cantilever, L/h = 10, nu = 0: beam theory (Timoshenko) tip deflection %.6f\n", Dim, reference);
  std::printf("  n (el./height)   FEM deflection   rel. error   rate\n");
  std::vector<double> errors;
  double last_rate = NAN;
  for (int n : refinements) {
    const double d = fem_tip_deflection<Dim>(n);
    errors.push_back(std::abs(d - reference) / reference);
    // Observed order in the mesh size h ~ 1/n.
    const double rate = errors.size() > 1 ? std::log(errors[errors.size() - 2] / errors.back()) /
                                                std::log(double(n) / refinements[errors.size() - 2])
                                          : NAN;
    last_rate = rate;
    std::printf("  %14d   %14.6f   %10.3e   %4.2f\n", n, d, errors.back(), rate);
    EXPECT_LT(d, reference * 1.01) << "linear simplices are too stiff in bending, never too soft";
  }
  EXPECT_LT(errors.back(), max_final_error);
  EXPECT_GT(last_rate, min_rate);
}

TEST(CantileverValidation, PlaneStrainTrianglesConvergeToBeamTheory) {
  expect_convergence<2>({4, 8, 16, 32}, 0.005, 1.8);
}

TEST(CantileverValidation, TetrahedraConvergeToBeamTheory) {
  expect_convergence<3>({2, 4, 6, 8}, 0.06, 1.6);
}

}  // namespace
}  // namespace tailor::cantilever_test
