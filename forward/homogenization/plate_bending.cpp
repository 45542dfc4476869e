#include "forward/homogenization/plate_bending.hpp"

#include <cmath>
#include <stdexcept>

#include "forward/core/assembler.hpp"
#include "forward/core/model.hpp"
#include "forward/core/timing.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {
namespace {

// Positions X + u_K(X) of the Kirchhoff field for the curvature kappa (see the header).
Vector bending_offset(const PeriodicCell& cell, const Eigen::Matrix2d& kappa, double mid_plane) {
  const Mesh& mesh = cell.mesh;
  Vector x0(3 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d X = mesh.rest_positions.row(v).transpose();
    const Eigen::Vector2d p = X.head<2>() - cell.origin.head<2>();
    const double z = X.z() - mid_plane;
    x0.segment<3>(3 * v) = X;
    x0.segment<2>(3 * v) += -z * (kappa * p);
    x0[3 * v + 2] += 0.5 * p.dot(kappa * p);
  }
  return x0;
}

}  // namespace

PlateBending plate_bending_stiffness(const PeriodicCell& cell, const Vector& youngs_modulus,
                                     const Vector& poisson_ratio) {
  if (cell.dim() != 3 || cell.periodic != std::vector<bool>{true, true, false})
    throw std::invalid_argument("plate_bending_stiffness: need a 3D cell periodic along a_1, a_2 only");
  if (std::abs(cell.lattice(2, 0)) > 1e-12 * cell.lattice.col(0).norm() ||
      std::abs(cell.lattice(2, 1)) > 1e-12 * cell.lattice.col(1).norm())
    throw std::invalid_argument("plate_bending_stiffness: a_1 and a_2 must lie in the x-y plane");
  const int ne = cell.mesh.num_elements();
  if (youngs_modulus.size() != ne || poisson_ratio.size() != ne)
    throw std::invalid_argument(
        "plate_bending_stiffness: need one Young's modulus and Poisson's ratio per element");
  Model model(3 * cell.mesh.num_vertices());
  model.parameter_layout().add("youngs_modulus", ne);
  model.parameter_layout().add("poisson_ratio", ne);
  model.add(std::make_unique<ElasticTerm<3>>(
      cell.mesh, std::shared_ptr<const Material<3>>(make_material<3>(MaterialKind::linear)), 0, ne));
  model.set_elimination(periodic_elimination(cell, Matrix::Zero(3, 3)));
  Vector p(2 * ne);
  p << youngs_modulus, poisson_ratio;

  PlateBending result;
  const Vector zs = cell.mesh.rest_positions.col(2);
  result.mid_plane = 0.5 * (zs.minCoeff() + zs.maxCoeff());
  ReducedAssembler assembler(model);
  SparseMatrix hessian = assembler.hessian_pattern_matrix();
  const Vector y0 = Vector::Zero(assembler.num_free());
  const Vector rest = bending_offset(cell, Eigen::Matrix2d::Zero(), result.mid_plane);
  model.elimination().set_offset(rest);
  assembler.evaluate(y0, p, nullptr, nullptr, &hessian);
  SparseCholesky factor;
  const auto t0 = Clock::now();
  const FactorizationResult f = factor.factorize(hessian);
  if (!f.success || !f.positive_definite)
    throw std::runtime_error("plate_bending_stiffness: the cell stiffness is not positive definite (" +
                             f.message + ")");
  result.factorization_seconds = seconds_since(t0);
  const Eigen::Matrix2d unit[3] = {Eigen::Matrix2d{{1.0, 0.0}, {0.0, 0.0}},
                                   Eigen::Matrix2d{{0.0, 0.0}, {0.0, 1.0}},
                                   Eigen::Matrix2d{{0.0, 0.5}, {0.5, 0.0}}};
  std::vector<Vector> offsets(3), displacements(3), forces(3);
  Matrix rhs(assembler.num_free(), 3);
  for (int I = 0; I < 3; ++I) {
    offsets[I] = bending_offset(cell, unit[I], result.mid_plane);
    model.elimination().set_offset(offsets[I]);
    Vector g;
    assembler.evaluate(y0, p, nullptr, &g, nullptr);
    rhs.col(I) = -g;
  }
  const Matrix fluctuations = factor.solve_columns(rhs);
  for (int I = 0; I < 3; ++I) {
    model.elimination().set_offset(offsets[I]);
    const Vector x = model.elimination().expand(fluctuations.col(I));
    displacements[I] = x - rest;
    forces[I] = model.gradient(x, p);  // K u_I (the linear material's gradient)
  }
  const double area = cell.lattice.col(0).head<2>().norm() * cell.lattice.col(1).head<2>().norm() *
                      std::abs(std::sin(std::atan2(cell.lattice(1, 1), cell.lattice(0, 1)) -
                                        std::atan2(cell.lattice(1, 0), cell.lattice(0, 0))));
  result.stiffness.resize(3, 3);
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J) result.stiffness(I, J) = displacements[I].dot(forces[J]) / area;
  return result;
}

double directional_bending_stiffness(const Matrix& D, const Vector& d) {
  if (D.rows() != 3 || D.cols() != 3 || d.size() != 2 || !(d.norm() > 0.0))
    throw std::invalid_argument("directional_bending_stiffness: need D (3 x 3) and a nonzero 2D direction");
  const Vector u = d.normalized();
  const Vector k{{u[0] * u[0], u[1] * u[1], 2.0 * u[0] * u[1]}};
  return k.dot(D * k);
}

}  // namespace tailor
