#include "forward/reduction/free_space.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <stdexcept>

#include "forward/core/assembler.hpp"

namespace tailor {

SparseMatrix free_stiffness(const Model& model, const Vector& x, const Vector& p) {
  ReducedAssembler assembler(model);
  SparseMatrix upper = assembler.hessian_pattern_matrix();
  const Vector y = model.elimination().restrict_state(x);
  assembler.evaluate(y, p, nullptr, nullptr, &upper, HessianMode::exact);
  SparseMatrix full = upper.selfadjointView<Eigen::Upper>();
  full.makeCompressed();
  return full;
}

SparseMatrix free_mass(const Model& model, const SparseMatrix& mass) {
  const SparseMatrix& s = model.elimination().basis();
  if (mass.rows() != model.num_dofs() || mass.cols() != model.num_dofs())
    throw std::invalid_argument("free_mass: the mass matrix is " + std::to_string(mass.rows()) + " x " +
                                std::to_string(mass.cols()) + ", the model has " +
                                std::to_string(model.num_dofs()) + " DOFs");
  SparseMatrix m = s.transpose() * mass * s;
  m.makeCompressed();
  return m;
}

Matrix rigid_body_motions(const Vector& x, int dim) {
  if (dim != 2 && dim != 3) throw std::invalid_argument("rigid_body_motions: dim must be 2 or 3");
  const Eigen::Index nv = x.size() / dim;
  Vector centroid = Vector::Zero(dim);
  for (Eigen::Index v = 0; v < nv; ++v) centroid += x.segment(dim * v, dim);
  centroid /= static_cast<double>(nv);
  const int rotations = dim == 3 ? 3 : 1;
  Matrix r = Matrix::Zero(x.size(), dim + rotations);
  for (Eigen::Index v = 0; v < nv; ++v) {
    const Vector d = x.segment(dim * v, dim) - centroid;
    for (int k = 0; k < dim; ++k) r(dim * v + k, k) = 1.0;
    if (dim == 2) {
      r(2 * v, 2) = -d[1];
      r(2 * v + 1, 2) = d[0];
    } else {
      // omega_a x d for the unit axes a = x, y, z.
      const Eigen::Vector3d dv(d[0], d[1], d[2]);
      for (int a = 0; a < 3; ++a) r.block<3, 1>(3 * v, 3 + a) = Eigen::Vector3d::Unit(a).cross(dv);
    }
  }
  return r;
}

Matrix admissible_rigid_modes(const Model& model, const Vector& x, int dim,
                              const SparseMatrix& free_mass_matrix) {
  const Elimination& elim = model.elimination();
  const Matrix rigid = rigid_body_motions(x, dim);
  // Free-space images y_k and the part of each rigid motion the constraints cannot follow.
  Matrix y(elim.num_free(), rigid.cols());
  for (Eigen::Index k = 0; k < rigid.cols(); ++k)
    y.col(k) = elim.restrict_state(elim.offset() + rigid.col(k)) - elim.restrict_state(elim.offset());
  const Matrix lost = Matrix(elim.basis() * y) - rigid;
  // Combinations c with |lost c| ~ 0 relative to |rigid c|: generalized eigenvectors of
  // (lost^T lost, rigid^T rigid) with tiny eigenvalues (an inadmissible motion loses at least
  // one vertex's share, ~1 / num_vertices; the dense solver's round-off is ~1e-16).
  const Matrix g_lost = lost.transpose() * lost, g_rigid = rigid.transpose() * rigid;
  Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> split(g_lost, g_rigid);
  std::vector<Eigen::Index> keep;
  for (Eigen::Index k = 0; k < split.eigenvalues().size(); ++k)
    if (split.eigenvalues()[k] < 1e-10) keep.push_back(k);
  if (keep.empty()) return Matrix(elim.num_free(), 0);
  Matrix modes = y * split.eigenvectors()(Eigen::all, keep);
  // M-orthonormalize: modes <- modes L^{-T} with L L^T = modes^T M modes.
  const Matrix gram = modes.transpose() * (free_mass_matrix * modes);
  Eigen::LLT<Matrix> llt(gram);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("admissible_rigid_modes: the mass matrix is singular on the rigid motions");
  return llt.matrixU().solve<Eigen::OnTheRight>(modes);
}

}  // namespace tailor
