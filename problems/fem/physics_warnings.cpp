#include "problems/fem/physics_warnings.hpp"

#include <cmath>
#include <exception>

#include "forward/core/format_number.hpp"
#include "forward/fem/mass.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "problems/fem/dynamic_scene.hpp"
#include "problems/fem/static_scene.hpp"

namespace tailor {

std::vector<std::string> locking_warnings(const Scene& scene) {
  std::vector<std::string> warnings;
  for (const MaterialSpec& m : scene.materials) {
    if (scene.mesh.order == 2 || m.spline_curves || m.poisson_ratio < kLockingPoissonRatio) continue;
    warnings.push_back(scene.source + ": " + m.key + ".poisson_ratio: " + format_number(m.poisson_ratio) +
                       " on linear elements: nearly incompressible material locks on linear tets and "
                       "triangles (displacements too small, by a factor growing like 1 / (1 - 2 nu) = " +
                       format_number(1.0 / (1.0 - 2.0 * m.poisson_ratio)) +
                       " in bending); use quadratic elements (\"mesh\": {..., \"order\": 2}, "
                       "docs/materials.md, \"Quadratic elements for nearly incompressible solids\"), "
                       "refine a lot, or use a lower Poisson's ratio");
  }
  return warnings;
}

std::vector<std::string> time_step_warnings(const Scene& scene) {
  if (!scene.dynamics || scene.dynamics->scheme != TimeScheme::newmark) return {};
  const double h = scene.dynamics->time_step;
  double period = 0.0;
  try {
    const StaticSetup setup = setup_static_scene(scene);
    if (setup.density.size() == 0 || setup.density.minCoeff() <= 0.0) return {};
    std::unique_ptr<Model> model = build_static_model(setup, 1.0);
    const Vector rest = setup.rest_state();
    model->elimination().set_offset(rest);
    const SparseMatrix mass = mass_matrix(setup.mesh, setup.density, MassLumping::consistent);
    ModalAnalysisOptions options;
    options.count = 1;
    const ModalAnalysis modes = modal_analysis(*model, setup.dim(), rest, setup.parameters(), mass, options);
    if (modes.eigenvalues.size() == 0 || !(modes.eigenvalues[0] > 0.0)) return {};
    period = 2.0 * M_PI / std::sqrt(modes.eigenvalues[0]);
  } catch (const std::exception&) {
    return {};  // advice only: a scene whose modes cannot be computed gets no warning
  }
  if (h <= 0.5 * period) return {};
  const double turn = 2.0 * std::atan(M_PI * h / period);
  return {scene.source + ": dynamics.time_step: h = " + format_number(h) + " is " + format_number(h / period) +
          " times the body's longest natural period (" + format_number(period) +
          "): Newmark resolves none of its vibrations (the lowest turns by " + format_number(turn / M_PI) +
          " pi per step instead of " + format_number(2.0 * h / period) +
          " pi) and does not damp them, so the energy oscillates from step to step; take h <= " +
          format_number(period / 20.0) + " to resolve that mode, or \"scheme\": \"implicit_euler\" or "
          "\"bdf2\" to damp it"};
}

}  // namespace tailor
