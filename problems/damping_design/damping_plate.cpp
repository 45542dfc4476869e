#include "problems/damping_design/damping_plate.hpp"

#include <stdexcept>

#include "forward/dynamics/damping_examples.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor {

void DampingPlate::set_controls(int i, const Vector& values) {
  const ExampleDamping& t = term();
  const int size =
      (i + 1 < t.num_examples() ? t.curve_begin(i + 1) : t.num_curve_parameters()) - t.curve_begin(i);
  if (values.size() != size)
    throw std::invalid_argument("example " + std::to_string(i) + " has " + std::to_string(size) +
                                " control values, got " + std::to_string(values.size()));
  p.segment(damping.curve_offset + t.curve_begin(i), size) = values;
}

double DampingPlate::rayleigh_decay_rate(int k) const {
  return 0.5 * (p[damping.alpha_offset] + p[damping.beta_offset] * omega[k] * omega[k]);
}

DampingPlate make_damping_plate(const DampingPlateOptions& o) {
  const std::size_t r = o.example_modes.size();
  if (!o.curves.empty() && o.curves.size() != r)
    throw std::invalid_argument("damping plate: one curve per example is needed");
  if (!o.controls.empty() && o.controls.size() != r)
    throw std::invalid_argument("damping plate: one set of control values per example is needed");
  DampingPlate plate;
  plate.mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(o.length, o.width, o.thickness),
                            o.cells_length, o.cells_width, o.cells_thickness);
  const Mesh& mesh = plate.mesh;
  const int m = mesh.num_elements(), n = 3 * mesh.num_vertices();
  plate.model = std::make_unique<Model>(n);
  Model& model = *plate.model;
  const int e_offset = model.parameter_layout().add("youngs_modulus", m);
  const int nu_offset = model.parameter_layout().add("poisson_ratio", m);
  model.add(
      std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::linear), e_offset, nu_offset));
  DynamicsSetup setup;
  setup.rayleigh = false;
  plate.dynamics = add_dynamics_terms(model, mesh, setup);
  plate.rest.resize(n);
  std::vector<int> fixed;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    plate.rest.segment(3 * v, 3) = mesh.rest_positions.row(v).transpose();
    if (mesh.rest_positions(v, 0) < 1e-9 * o.length)
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
    if (mesh.rest_positions(v, 0) > o.length * (1 - 1e-9)) plate.tip_vertices.push_back(v);
  }
  model.set_elimination(Elimination::dirichlet(fixed, plate.rest));
  Vector p0 = Vector::Zero(model.parameter_layout().size());
  p0.segment(e_offset, m).setConstant(o.youngs_modulus);
  p0.segment(nu_offset, m).setConstant(o.poisson_ratio);
  p0.segment(plate.dynamics.density_offset, m).setConstant(o.density);

  ExampleDampingSetup damping;
  for (std::size_t i = 0; i < r; ++i) {
    DampingExampleSpec spec;
    spec.source = DampingExampleSpec::Source::eigenmode;
    spec.mode = o.example_modes[i];
    if (!o.curves.empty()) spec.curve = o.curves[i];
    damping.examples.push_back(spec);
  }
  plate.damping = add_example_damping(model, mesh, plate.dynamics.inertia->mass_ptr(), p0, damping);
  plate.p = Vector::Zero(model.parameter_layout().size());
  plate.p.head(p0.size()) = p0;
  plate.p[plate.damping.alpha_offset] = o.alpha;
  plate.p[plate.damping.beta_offset] = o.beta;
  for (std::size_t i = 0; i < r; ++i) {
    const int size = static_cast<int>(damping.examples[i].curve.knots.size());
    plate.set_controls(static_cast<int>(i), o.controls.empty() ? Vector::Ones(size) : o.controls[i]);
  }
  plate.mass = plate.dynamics.inertia->mass().matrix(plate.p);
  plate.stiffness = plate.term().base().rest_stiffness(plate.p);
  std::vector<int> indices(static_cast<std::size_t>(o.measured_modes));
  for (int k = 0; k < o.measured_modes; ++k) indices[static_cast<std::size_t>(k)] = k;
  Vector lambda;
  plate.modes =
      eigenmode_examples(plate.stiffness, plate.mass, model.elimination().basis(), indices, &lambda);
  plate.omega = lambda.array().sqrt().matrix();
  return plate;
}

}  // namespace tailor
