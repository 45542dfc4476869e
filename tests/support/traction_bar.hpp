#pragma once
// A clamped 3D bar (4 x 1 x 1, clamped at x = 0) bent by an end traction (0, 0.3, -1) * load,
// with the inverse problem the adjoint tests use: per-element log E (LogModuliMap) and a
// target for every tip DOF (DofTargetObjective, Tikhonov weight c).
#include <memory>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "inverse_fixtures.hpp"

namespace tailor::testing {

struct TractionBar {
  Mesh mesh;
  std::unique_ptr<Model> model;
  Vector rest, p0;
  std::vector<int> tip_dofs;

  TractionBar(MaterialKind kind, double load, const Eigen::Vector3i& cells = Eigen::Vector3i(4, 1, 1))
      : mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), cells[0], cells[1], cells[2])) {
    const int m = mesh.num_elements();
    model = std::make_unique<Model>(3 * mesh.num_vertices());
    model->parameter_layout().add("youngs_modulus", m);
    model->parameter_layout().add("poisson_ratio", m);
    model->add(elastic_term<3>(mesh, kind));
    const Eigen::MatrixXi end_facets =
        boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[0] > 4 - 1e-9; });
    model->add(
        std::make_unique<ExternalForceTerm>(traction_forces(mesh, end_facets, Eigen::Vector3d(0, 0.3 * load, -load))));
    rest = rest_state(mesh);
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.rest_positions(v, 0) < 1e-9)
        for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
      if (mesh.rest_positions(v, 0) > 4 - 1e-9)
        for (int k = 0; k < 3; ++k) tip_dofs.push_back(3 * v + k);
    }
    model->set_elimination(Elimination::dirichlet(fixed, rest));
    p0 = heterogeneous_parameters(mesh, 1000.0, 0.3);
  }

  StaticFunctional functional(double c = 0.0, StaticFunctionalOptions options = {}) {
    const int m = mesh.num_elements();
    Vector target(tip_dofs.size());
    for (std::size_t k = 0; k < tip_dofs.size(); ++k) target[k] = rest[tip_dofs[k]] + (k % 3 == 2 ? -0.3 : 0.05);
    auto map = std::make_shared<LogModuliMap>(p0, m);
    auto objective = std::make_shared<DofTargetObjective>(tip_dofs, target, c, m);
    return StaticFunctional(*model, map, objective, model->elimination().restrict_state(rest), options);
  }
  Vector z0() const { return p0.head(mesh.num_elements()).array().log().matrix(); }
};

}  // namespace tailor::testing
