#pragma once
// The benchmark scene shared by bench/*.cpp: a unit block of n^3 cells of 6 tets (n chosen
// to match a target tet count), clamped at its base z = 0, with a shear-and-compression
// traction (0.05 E, 0, -0.05 E) on its top face that deforms it by roughly 20-30%.
// Parameters p = [E = 1e6 per element, nu = 0.4 per element].
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::bench {

struct LoadedBlock {
  Mesh mesh;
  std::unique_ptr<Model> model;
  Vector rest;                    // rest positions as a state vector
  Vector parameters;              // [E..., nu...]
  std::vector<int> top_vertices;  // vertices of the loaded face
  Vector rest_unknowns() const { return model->elimination().restrict_state(rest); }
};

inline LoadedBlock make_loaded_block(int target_tets, MaterialKind material) {
  constexpr double kYoung = 1e6;
  LoadedBlock b;
  const int n = std::max(1, static_cast<int>(std::lround(std::cbrt(target_tets / 6.0))));
  b.mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), n, n, n);
  const Mesh& mesh = b.mesh;
  const int m = mesh.num_elements();
  b.model = std::make_unique<Model>(3 * mesh.num_vertices());
  b.model->parameter_layout().add("youngs_modulus", m);
  b.model->parameter_layout().add("poisson_ratio", m);
  b.model->add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(material), 0, m));
  const Eigen::MatrixXi top =
      boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[2] > 1 - 1e-9; });
  b.model->add(std::make_unique<ExternalForceTerm>(
      traction_forces(mesh, top, Eigen::Vector3d(0.05 * kYoung, 0.0, -0.05 * kYoung))));
  b.rest.resize(3 * mesh.num_vertices());
  std::vector<int> fixed;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    b.rest.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
    if (mesh.rest_positions(v, 2) < 1e-9)
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
    if (mesh.rest_positions(v, 2) > 1 - 1e-9) b.top_vertices.push_back(v);
  }
  b.model->set_elimination(Elimination::dirichlet(fixed, b.rest));
  b.parameters.resize(2 * m);
  b.parameters.head(m).setConstant(kYoung);
  b.parameters.tail(m).setConstant(0.4);
  return b;
}

}  // namespace tailor::bench
