// Draping and pulling the macro-scale interlocking sheet (see macro_drape.hpp).
#include "forward/interlocking/macro_drape.hpp"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "forward/core/model.hpp"
#include "forward/fem/loads.hpp"
#include "forward/interlocking/macro_drape_terms.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::interlocking {

double macro_uniaxial_limit(const BoundaryFit& fit) { return fit.radius(1.0 / std::sqrt(2.0)); }

DrapeResult drape_over_sphere(const BoundaryFit& fit, const DrapeSpec& spec) {
  if (!(spec.width > 0.0) || spec.divisions < 2 || spec.divisions % 2 != 0)
    throw std::invalid_argument("drape_over_sphere: needs width > 0 and an even number of divisions >= 2");
  if (!(spec.areal_weight >= 0.0)) throw std::invalid_argument("drape_over_sphere: needs areal_weight >= 0");
  DrapeResult result;
  const double h = 0.5 * spec.width;
  result.flat =
      rectangle_triangle_mesh(Eigen::Vector2d(-h, -h), Eigen::Vector2d(h, h), spec.divisions, spec.divisions);
  const Mesh& flat = result.flat;
  const int nv = flat.num_vertices();
  Model model(3 * nv);
  auto& sheet = model.add(std::make_unique<MacroSheetTerm>(flat, fit, spec.material));
  if (spec.bending_stiffness > 0.0)
    model.add(std::make_unique<QuadraticBendingTerm>(flat, spec.bending_stiffness));
  auto& sphere = model.add(std::make_unique<SphereObstacleTerm>(
      nv, Eigen::Vector3d::Zero(), spec.sphere_radius, spec.contact_activation, spec.contact_stiffness));
  // Gravity: a third of each triangle's weight on each of its vertices (consistent for linear
  // shape functions).
  Vector forces = Vector::Zero(3 * nv);
  for (int k = 0; k < flat.num_elements(); ++k)
    for (int a = 0; a < 3; ++a)
      forces[3 * flat.elements(k, a) + 2] -=
          spec.areal_weight * sheet.triangles().areas[static_cast<std::size_t>(k)] / 3.0;
  model.add(std::make_unique<ExternalForceTerm>(forces, "gravity"));
  Vector x0(3 * nv);
  const double z0 = spec.sphere_radius + 0.5 * spec.contact_activation;
  for (int v = 0; v < nv; ++v)
    x0.segment<3>(3 * v) << flat.rest_positions(v, 0), flat.rest_positions(v, 1), z0;
  const int centre = spec.divisions / 2 + (spec.divisions + 1) * (spec.divisions / 2);
  model.set_elimination(Elimination::dirichlet({3 * centre, 3 * centre + 1, 3 * (centre + 1) + 1}, x0));
  NewtonSolver solver(model, spec.newton);
  Vector y = model.elimination().restrict_state(x0);
  result.newton = solver.solve(Vector(), y);
  result.positions = model.state(y, Vector());
  result.principal_strains = sheet.principal_strains(result.positions);
  result.margins = sheet.margins(result.positions);
  result.gaps = sphere.gaps(result.positions);
  for (int k = 0; k < result.margins.size(); ++k)
    if (result.margins[k] < spec.material.barrier_activation) ++result.barrier_elements;
  for (int v = 0; v < nv; ++v)
    if (result.gaps[v] < spec.contact_activation) ++result.contact_vertices;
  for (int k = 0; k < flat.num_elements(); ++k)
    for (int a = 0; a < 3; ++a) {
      const double e = (result.positions.segment<3>(3 * flat.elements(k, a)) -
                        result.positions.segment<3>(3 * flat.elements(k, (a + 1) % 3)))
                           .norm();
      result.sagitta_bound = std::max(result.sagitta_bound, e * e / (8.0 * spec.sphere_radius));
    }
  return result;
}

PullResult pull_strip(const BoundaryFit& fit, const MacroSheetMaterial& material, double traction,
                      double length, double width, int nx, int ny) {
  if (!(length > 0.0) || !(width > 0.0) || nx < 1 || ny < 1 || !(traction >= 0.0))
    throw std::invalid_argument("pull_strip: needs length, width > 0, nx, ny >= 1, traction >= 0");
  const Mesh flat =
      rectangle_triangle_mesh(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(length, width), nx, ny);
  const int nv = flat.num_vertices();
  Model model(3 * nv);
  auto& sheet = model.add(std::make_unique<MacroSheetTerm>(flat, fit, material));
  Vector forces = Vector::Zero(3 * nv);
  std::vector<int> fixed;
  Vector x0(3 * nv);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int v = i + (nx + 1) * j;
      x0.segment<3>(3 * v) << flat.rest_positions(v, 0), flat.rest_positions(v, 1), 0.0;
      fixed.push_back(3 * v + 1);
      fixed.push_back(3 * v + 2);
      if (i == 0) fixed.push_back(3 * v);
      // The right edge's share of the traction: edge length / ny, halved at the corners.
      if (i == nx) forces[3 * v] = traction * width / ny * (j == 0 || j == ny ? 0.5 : 1.0);
    }
  model.add(std::make_unique<ExternalForceTerm>(forces, "pull"));
  model.set_elimination(Elimination::dirichlet(fixed, x0));
  NewtonOptions options;
  options.max_iterations = 300;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(x0);
  PullResult result;
  result.newton = solver.solve(Vector(), y);
  const Vector x = model.state(y, Vector());
  double stretch = 0.0;
  for (int j = 0; j <= ny; ++j) stretch += x[3 * (nx + (nx + 1) * j)] / length - 1.0;
  result.strain = stretch / (ny + 1);
  result.min_margin = sheet.margins(x).minCoeff();
  return result;
}

}  // namespace tailor::interlocking
