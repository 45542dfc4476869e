#pragma once
// Small dynamic models for tests: a cantilever bar of tets clamped at x = 0, with an elastic
// term, inertia, optional gravity and Rayleigh damping, and parameters
// p = [youngs_modulus (m), poisson_ratio (m), density (m), (alpha, beta)].
#include <memory>

#include "fem_fixtures.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/dynamics/time_integrator.hpp"

namespace tailor::testing {

struct CantileverOptions {
  MaterialKind material = MaterialKind::neo_hookean;
  MassLumping lumping = MassLumping::consistent;
  double length = 4.0;
  int cells = 4;  // along the length; 1 x 1 across
  double youngs_modulus = 1000.0, poisson_ratio = 0.3, density = 1.0;
  std::optional<Eigen::VectorXd> gravity;
  bool rayleigh = false;
  double alpha = 0.0, beta = 0.0;
  bool clamp = true;
};

struct Cantilever {
  Mesh mesh;
  std::unique_ptr<Model> model;
  DynamicTerms terms;
  Vector rest, p;
  std::vector<int> tip_vertices, fixed_dofs;

  explicit Cantilever(const CantileverOptions& o = {}) {
    mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(o.length, 1, 1), o.cells, 1, 1);
    const int m = mesh.num_elements();
    model = std::make_unique<Model>(3 * mesh.num_vertices());
    model->parameter_layout().add("youngs_modulus", m);
    model->parameter_layout().add("poisson_ratio", m);
    model->add(elastic_term<3>(mesh, o.material));
    terms = add_dynamics_terms(*model, mesh, DynamicsSetup{o.lumping, o.gravity, o.rayleigh});
    rest = rest_state(mesh);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.rest_positions(v, 0) < 1e-9)
        for (int k = 0; k < 3; ++k) fixed_dofs.push_back(3 * v + k);
      if (mesh.rest_positions(v, 0) > o.length - 1e-9) tip_vertices.push_back(v);
    }
    if (o.clamp)
      model->set_elimination(Elimination::dirichlet(fixed_dofs, rest));
    else
      model->set_elimination(Elimination::identity(model->num_dofs()));
    p = Vector::Zero(model->parameter_layout().size());
    p.head(m).setConstant(o.youngs_modulus);
    p.segment(m, m).setConstant(o.poisson_ratio);
    p.segment(terms.density_offset, m).setConstant(o.density);
    if (o.rayleigh) {
      p[terms.alpha_offset] = o.alpha;
      p[terms.beta_offset] = o.beta;
    }
  }
  int num_elements() const { return mesh.num_elements(); }
};

// The descent solver's test bar: `cells` x 1 x 1 cells of 6 tets, cells / 12 long, E = 1e4,
// under gravity, with Rayleigh damping (alpha 0.1, beta 1e-3).
inline CantileverOptions descent_bar_options(int cells, MaterialKind material = MaterialKind::neo_hookean) {
  CantileverOptions o;
  o.material = material;
  o.cells = cells;
  o.length = cells / 12.0;
  o.youngs_modulus = 1e4;
  o.gravity = Eigen::Vector3d(0, 0, -9.81);
  o.rayleigh = true;
  o.alpha = 0.1;
  o.beta = 1e-3;
  return o;
}

}  // namespace tailor::testing
