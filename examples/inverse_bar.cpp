// A user's own inverse problem against an installed tailor: a Neo-Hookean bar of two materials
// is clamped at x = 0 and pulled at x = 4; from the displacements of its surface vertices
// (synthesised here from the true moduli) recover the Young's modulus of each half.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/generate.hpp"
#include "objectives/target_positions.hpp"
#include "optimizers/optimizer.hpp"

using namespace tailor;

int main() {
  const double length = 4.0, true_moduli[2] = {1e5, 3e5};
  const Mesh mesh = box_tet_mesh({0, 0, 0}, {length, 1, 1}, 8, 2, 2);
  const int m = mesh.num_elements(), n = mesh.num_vertices();

  // p = [E_0 .. E_{m-1}, nu_0 .. nu_{m-1}]: one Young's modulus and Poisson's ratio per tet.
  Model model(3 * n);
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m));

  // A uniform traction on the end face x = length (the boundary facets lying in it).
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  std::vector<int> end_face;
  for (int k = 0; k < facets.rows(); ++k)
    if ((mesh.rest_positions(facets.row(k), 0).array() > length - 1e-9).all()) end_face.push_back(k);
  model.add(std::make_unique<ExternalForceTerm>(
      traction_forces(mesh, facets(end_face, Eigen::all), Eigen::Vector3d(1e4, 0, -5e2))));

  // Clamp the face x = 0; observe every other vertex on the surface (what a camera sees).
  Vector rest(3 * n);
  std::vector<bool> on_surface(n, false);
  for (int k = 0; k < facets.size(); ++k) on_surface[facets(k)] = true;
  std::vector<int> fixed, observed;
  for (int v = 0; v < n; ++v) {
    rest.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
    if (mesh.rest_positions(v, 0) < 1e-9)
      fixed.insert(fixed.end(), {3 * v, 3 * v + 1, 3 * v + 2});
    else if (on_surface[v])
      observed.push_back(v);
  }
  model.set_elimination(Elimination::dirichlet(fixed, rest));
  const Vector rest_y = model.elimination().restrict_state(rest);

  // Design z = log(E_left, E_right): each scattered to its half's tets; Poisson's ratio stays 0.3.
  std::vector<int> half(m);
  for (int e = 0; e < m; ++e)
    half[e] = mesh.rest_positions(mesh.elements.row(e), 0).mean() < length / 2 ? 0 : 1;
  Vector base = Vector::Zero(2 * m);
  base.tail(m).setConstant(0.3);
  const ParameterizationPtr design =
      embed_blocks(base, {{0, compose(region_scatter_map(half, 2), exp_map(2))}});

  // Synthetic observations: the surface displacements at equilibrium under the true moduli.
  NewtonSolver newton(model);
  Vector y = rest_y;
  const Vector true_z = Eigen::Vector2d(std::log(true_moduli[0]), std::log(true_moduli[1]));
  const NewtonResult solve = newton.solve(design->apply(true_z), y);
  if (!solve.converged()) {
    std::printf("the forward solve at the true moduli failed:\n%s", solve.report().c_str());
    return 1;
  }
  const Vector x = model.elimination().expand(y);
  Matrix displacements(observed.size(), 3);
  for (std::size_t k = 0; k < observed.size(); ++k)
    displacements.row(k) = (x - rest).segment<3>(3 * observed[k]).transpose();
  auto objective =
      std::make_shared<TargetPositions>(TargetPositions::displacements(mesh, observed, displacements));

  // The reduced functional J(z) and a check of its adjoint gradient, from a start 3x off.
  StaticFunctional functional(model, design, objective, rest_y);
  const Vector z0 = Eigen::Vector2d(std::log(3 * true_moduli[0]), std::log(true_moduli[1] / 3));
  const TaylorTestResult taylor = taylor_test(functional, z0);
  std::printf("%s", taylor.table().c_str());
  if (!taylor.passed()) return 1;

  // Recover the moduli with NLopt's L-BFGS, within 1e3 .. 1e8.
  OptimizerOptions options;
  options.backend = OptimizerBackend::nlopt_lbfgs;
  options.max_iterations = 500;
  options.gradient_tolerance = 1e-13;
  const Bounds bounds{Vector::Constant(2, std::log(1e3)), Vector::Constant(2, std::log(1e8))};
  const OptimizerResult result = minimize(functional, z0, bounds, {}, options);
  std::printf("%s (%s): %zu iterations, %d forward solves\n", to_string(result.status).c_str(),
              result.message.c_str(), result.history.size(), functional.counters().forward_solves);
  bool recovered = true;
  for (int i = 0; i < 2; ++i) {
    const double modulus = std::exp(result.z[i]), error = std::abs(modulus / true_moduli[i] - 1);
    std::printf("  E_%s = %.9g  (true %g, relative error %.1e)\n", i == 0 ? "left " : "right", modulus,
                true_moduli[i], error);
    recovered = recovered && error < 1e-6;
  }
  return recovered ? 0 : 1;
}
