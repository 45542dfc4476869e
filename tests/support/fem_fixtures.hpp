#pragma once
// Small FEM models for tests: a mesh, one elastic term over all elements, and parameters.
#include <memory>
#include <Eigen/Geometry>
#include <random>

#include "forward/core/model.hpp"
#include "forward/fem/elastic_term.hpp"
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

}  // namespace tailor::testing
