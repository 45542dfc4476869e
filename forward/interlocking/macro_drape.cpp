// Draping and pulling the macro-scale interlocking sheet (see macro_drape.hpp).
#include "forward/interlocking/macro_drape.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "forward/core/model.hpp"
#include "forward/fem/loads.hpp"
#include "forward/interlocking/macro_drape_terms.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::interlocking {

double macro_uniaxial_limit(const MacroStrainSet& set, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return set.radius_along(Eigen::Vector3d(c * c, s * s, c * s));
}

DrapeResult drape_over_sphere(const MacroStrainSet& set, const DrapeSpec& spec) {
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
  auto& sheet = model.add(std::make_unique<MacroSheetTerm>(flat, set, spec.material));
  if (spec.bending_stiffness > 0.0)
    model.add(std::make_unique<QuadraticBendingTerm>(flat, spec.bending_stiffness));
  const BendingLimitTerm* limits = nullptr;
  if (spec.bending_limits)
    limits = &model.add(std::make_unique<BendingLimitTerm>(flat, spec.bending_fit, spec.curvature_barrier));
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
  if (limits) {
    result.hinge_curvatures = limits->curvatures(result.positions);
    result.hinge_margins = limits->margins(result.positions);
  }
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

namespace {
Mesh turned_strip(const Mesh& strip, double angle);
}  // namespace

PullResult pull_strip(const MacroStrainSet& set, const MacroSheetMaterial& material, double traction) {
  PullSpec spec;
  spec.traction = traction;
  return pull_strip(set, material, spec);
}

PullResult pull_strip(const MacroStrainSet& set, const MacroSheetMaterial& material, const PullSpec& spec) {
  const int nx = spec.nx, ny = spec.ny;
  if (!(spec.length > 0.0) || !(spec.width > 0.0) || nx < 1 || ny < 1 || !(spec.traction >= 0.0) ||
      !(spec.lateral_traction >= 0.0))
    throw std::invalid_argument("pull_strip: needs length, width > 0, nx, ny >= 1, tractions >= 0");
  const Mesh strip =
      rectangle_triangle_mesh(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(spec.length, spec.width), nx, ny);
  const Mesh flat = turned_strip(strip, spec.angle);
  const int nv = flat.num_vertices();
  Model model(3 * nv);
  auto& sheet = model.add(std::make_unique<MacroSheetTerm>(flat, set, material));
  Vector forces = Vector::Zero(3 * nv);
  std::vector<int> fixed;
  Vector x0(3 * nv);
  const bool biaxial = spec.lateral_traction > 0.0;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int v = i + (nx + 1) * j;
      x0.segment<3>(3 * v) << strip.rest_positions(v, 0), strip.rest_positions(v, 1), 0.0;
      if (!biaxial || j == 0) fixed.push_back(3 * v + 1);
      fixed.push_back(3 * v + 2);
      if (i == 0) fixed.push_back(3 * v);
      // The right (top) edge's share of the traction: edge length / divisions, halved at the corners.
      if (i == nx) forces[3 * v] = spec.traction * spec.width / ny * (j == 0 || j == ny ? 0.5 : 1.0);
      if (biaxial && j == ny)
        forces[3 * v + 1] = spec.lateral_traction * spec.length / nx * (i == 0 || i == nx ? 0.5 : 1.0);
    }
  std::sort(fixed.begin(), fixed.end());
  model.add(std::make_unique<ExternalForceTerm>(forces, "pull"));
  model.set_elimination(Elimination::dirichlet(fixed, x0));
  NewtonOptions options;
  options.max_iterations = 300;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(x0);
  PullResult result;
  result.newton = solver.solve(Vector(), y);
  const Vector x = model.state(y, Vector());
  double stretch = 0.0, lateral = 0.0;
  for (int j = 0; j <= ny; ++j) stretch += x[3 * (nx + (nx + 1) * j)] / spec.length - 1.0;
  for (int i = 0; i <= nx; ++i) lateral += x[3 * (i + (nx + 1) * ny) + 1] / spec.width - 1.0;
  result.strain = stretch / (ny + 1);
  result.lateral_strain = lateral / (nx + 1);
  result.min_margin = sheet.margins(x).minCoeff();
  return result;
}

namespace {

// The rest sheet in material coordinates of a strip [0, length] x [0, width] whose x is the material
// direction (cos angle, sin angle): the strip turned by +angle (a rotation keeps the triangles
// counter-clockwise).
Mesh turned_strip(const Mesh& strip, double angle) {
  Mesh flat = strip;
  Eigen::Matrix2d turn;
  turn << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  for (int v = 0; v < flat.num_vertices(); ++v)
    flat.rest_positions.row(v) = (turn * strip.rest_positions.row(v).transpose()).transpose();
  return flat;
}

}  // namespace

BendResult bend_strip(const MacroStrainSet& set, const MacroSheetMaterial& material, const BendingLimitFit& fit,
                      const BendSpec& spec) {
  const int nx = spec.nx, ny = spec.ny;
  if (!(spec.length > 0.0) || !(spec.width > 0.0) || nx < 4 || ny < 1 || !(spec.moment >= 0.0))
    throw std::invalid_argument("bend_strip: needs length, width > 0, nx >= 4, ny >= 1, moment >= 0");
  const Mesh strip =
      rectangle_triangle_mesh(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(spec.length, spec.width), nx, ny);
  const Mesh flat = turned_strip(strip, spec.angle);
  const int nv = flat.num_vertices();
  Model model(3 * nv);
  model.add(std::make_unique<MacroSheetTerm>(flat, set, material));
  if (spec.bending_stiffness > 0.0) model.add(std::make_unique<QuadraticBendingTerm>(flat, spec.bending_stiffness));
  const auto& limits = model.add(std::make_unique<BendingLimitTerm>(flat, fit, spec.barrier));
  const double h = spec.length / nx;
  const double force = spec.moment * spec.width / h;  // the couple's force, shared along the column
  Vector forces = Vector::Zero(3 * nv);
  std::vector<int> fixed;
  Vector x0(3 * nv);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int v = i + (nx + 1) * j;
      x0.segment<3>(3 * v) << strip.rest_positions(v, 0), strip.rest_positions(v, 1), 0.0;
      if (i <= 1)
        for (int d = 0; d < 3; ++d) fixed.push_back(3 * v + d);
      const double share = (j == 0 || j == ny ? 0.5 : 1.0) / ny;
      if (i == nx) forces[3 * v + 2] = force * share;
      if (i == nx - 1) forces[3 * v + 2] = -force * share;
    }
  model.add(std::make_unique<ExternalForceTerm>(forces, "couple"));
  model.set_elimination(Elimination::dirichlet(fixed, x0));
  NewtonOptions options;
  options.max_iterations = 300;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(x0);
  BendResult result;
  result.newton = solver.solve(Vector(), y);
  const Vector x = model.state(y, Vector());
  const Eigen::VectorXd kappa = limits.curvatures(x);
  const Eigen::VectorXd angles = limits.normal_angles();
  result.min_margin = limits.margins(x).minCoeff();
  // Hinges across the strip (normal along the strip's x, the material direction at `angle`), away
  // from the clamp and the couple: the edges x = i h, 2 <= i <= nx - 2.
  double sum = 0.0;
  int count = 0;
  for (int k = 0; k < kappa.size(); ++k) {
    const double off = std::remainder(angles[k] - spec.angle, M_PI);
    if (std::abs(off) < 1e-6) {
      sum += kappa[k];
      result.max_curvature = std::max(result.max_curvature, kappa[k]);
      ++count;
    }
  }
  result.curvature = count > 0 ? sum / count : 0.0;
  return result;
}

}  // namespace tailor::interlocking
