#pragma once
// Beams and blocks for the model-reduction tests: a mesh, an elastic model (clamped at x = 0
// or free), rest state, parameters p = [E..., nu...] and the consistent mass matrix.
#include <memory>

#include "../../support/fem_fixtures.hpp"
#include "forward/fem/mass.hpp"

namespace tailor::testing {

struct ElasticBody {
  Mesh mesh;
  std::unique_ptr<Model> model;
  Vector rest, p;
  SparseMatrix mass;
  int dim() const { return mesh.dim(); }
};

// Box [0, size] (2D: rectangle) with `cells` cells per axis; clamped on the face x = 0 or free.
inline ElasticBody elastic_body(const Eigen::VectorXd& size, const Eigen::VectorXi& cells, MaterialKind kind,
                                bool clamped, double youngs_modulus = 1000.0, double poisson_ratio = 0.3,
                                double density = 1.0) {
  ElasticBody b;
  const int dim = static_cast<int>(size.size());
  b.mesh = dim == 3
               ? box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(size), cells[0], cells[1], cells[2])
               : rectangle_triangle_mesh(Eigen::Vector2d::Zero(), Eigen::Vector2d(size), cells[0], cells[1]);
  const int m = b.mesh.num_elements();
  b.model = std::make_unique<Model>(dim * b.mesh.num_vertices());
  b.model->parameter_layout().add("youngs_modulus", m);
  b.model->parameter_layout().add("poisson_ratio", m);
  if (dim == 3)
    b.model->add(elastic_term<3>(b.mesh, kind));
  else
    b.model->add(elastic_term<2>(b.mesh, kind));
  b.rest = rest_state(b.mesh);
  if (clamped) {
    std::vector<int> fixed;
    for (int v = 0; v < b.mesh.num_vertices(); ++v)
      if (b.mesh.rest_positions(v, 0) < 1e-9)
        for (int k = 0; k < dim; ++k) fixed.push_back(dim * v + k);
    b.model->set_elimination(Elimination::dirichlet(fixed, b.rest));
  }
  b.p.resize(2 * m);
  b.p.head(m).setConstant(youngs_modulus);
  b.p.tail(m).setConstant(poisson_ratio);
  b.mass = mass_matrix(b.mesh, Eigen::VectorXd::Constant(m, density), MassLumping::consistent);
  return b;
}

}  // namespace tailor::testing
