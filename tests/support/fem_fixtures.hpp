#pragma once
// Small FEM models for tests: a mesh, one elastic term over all elements, and parameters.
#include <memory>
#include <Eigen/Geometry>
#include <random>

#include "forward/core/model.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::testing {

inline Mesh small_mesh(int dim) {
  if (dim == 3) return box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 2, 1, 1);
  return rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 2, 2);
}

// Rest positions as a flat state vector.
inline Vector rest_state(const Mesh& mesh) {
  Vector x(mesh.dim() * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) x.segment(mesh.dim() * v, mesh.dim()) = mesh.rest_positions.row(v).transpose();
  return x;
}

// x_v = A X_v + c for every vertex.
inline Vector affine_state(const Mesh& mesh, const Matrix& A, const Vector& c) {
  Vector x(mesh.dim() * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    x.segment(mesh.dim() * v, mesh.dim()) = A * mesh.rest_positions.row(v).transpose() + c;
  return x;
}

// Per-element Young's moduli in [0.5, 1.5] * E and a uniform Poisson ratio: p = [E..., nu...].
inline Vector heterogeneous_parameters(const Mesh& mesh, double youngs_modulus, double poisson_ratio, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  const int m = mesh.num_elements();
  Vector p(2 * m);
  for (int e = 0; e < m; ++e) p[e] = youngs_modulus * u(rng);
  p.tail(m).setConstant(poisson_ratio);
  return p;
}

template <int Dim>
std::unique_ptr<ElasticTerm<Dim>> elastic_term(const Mesh& mesh, MaterialKind kind) {
  return std::make_unique<ElasticTerm<Dim>>(mesh, make_material<Dim>(kind), 0, mesh.num_elements());
}

inline Matrix rotation(int dim, double angle) {
  if (dim == 2) return Eigen::Rotation2Dd(angle).toRotationMatrix();
  return Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

// A 2 x 1 x 1 bar of `cells` tets cells and one material, clamped at x = 0, with the nodal
// force `tip_force` on every vertex of x = 2. Parameters p = [E per element, nu per element].
struct ClampedBar {
  Mesh mesh;
  Model model;
  Vector rest;  // the rest state's free unknowns
  ClampedBar(MaterialKind kind, const Eigen::Vector3i& cells, const Eigen::Vector3d& tip_force)
      : mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), cells[0], cells[1], cells[2])),
        model(3 * mesh.num_vertices()) {
    const int m = mesh.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<3>(mesh, kind));
    Vector forces = Vector::Zero(3 * mesh.num_vertices());
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double x = mesh.rest_positions(v, 0);
      if (x < 1e-12)
        for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
      if (x > 2.0 - 1e-12) forces.segment<3>(3 * v) = tip_force;
    }
    model.add(std::make_unique<ExternalForceTerm>(forces));
    model.set_elimination(Elimination::dirichlet(fixed, rest_state(mesh)));
    rest = model.elimination().restrict_state(rest_state(mesh));
  }
};

}  // namespace tailor::testing
