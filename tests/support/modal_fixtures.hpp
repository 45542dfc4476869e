#pragma once
// Modal analysis of a test cantilever (K phi = lambda M phi on the free DOFs, K the rest
// stiffness) and the modal coordinates of a state: q = phi^T M (x - X), qdot = phi^T M v.
#include <cmath>

#include "dynamics_fixtures.hpp"
#include "forward/reduction/generalized_eigen.hpp"

namespace tailor::testing {

struct CantileverModes {
  Vector omega;   // angular frequencies [rad / time], ascending
  Matrix shapes;  // full-space mode shapes S phi (zero on fixed DOFs), M-orthonormal
  SparseMatrix mass;
};

inline CantileverModes cantilever_modes(const Cantilever& c, const Vector& p, int count) {
  const SparseMatrix K = c.model->terms()[0]->hessian(c.rest, p, HessianMode::exact);
  const SparseMatrix M = c.terms.inertia->mass().matrix(p);
  const SparseMatrix& S = c.model->elimination().basis();
  const SparseMatrix Kf = S.transpose() * K * S, Mf = S.transpose() * M * S;
  const GeneralizedEigenResult eig = generalized_eigenpairs(Kf, Mf, count);
  if (!eig.success) throw std::runtime_error("cantilever_modes: " + eig.message);
  CantileverModes modes;
  modes.omega = eig.eigenvalues.array().sqrt().matrix();
  modes.shapes = S * eig.eigenvectors;
  modes.mass = M;
  return modes;
}

inline double modal_coordinate(const CantileverModes& m, int k, const Vector& w) {
  return m.shapes.col(k).dot(m.mass * w);
}

}  // namespace tailor::testing
