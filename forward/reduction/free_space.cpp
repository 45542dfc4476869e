#include "forward/reduction/free_space.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/core/assembler.hpp"
#include "forward/core/symmetric_eigen.hpp"

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
  Vector split_values;
  Matrix split_vectors;
  if (!generalized_symmetric_eigen(g_lost, g_rigid, split_values, split_vectors))
    throw std::runtime_error("admissible_rigid_modes: the rigid motions are linearly dependent");
  std::vector<Eigen::Index> keep;
  for (Eigen::Index k = 0; k < split_values.size(); ++k)
    if (split_values[k] < 1e-10) keep.push_back(k);
  if (keep.empty()) return Matrix(elim.num_free(), 0);
  Matrix modes = y * split_vectors(Eigen::all, keep);
  // M-orthonormalize: modes <- modes L^{-T} with L L^T = modes^T M modes.
  const Matrix gram = modes.transpose() * (free_mass_matrix * modes);
  Eigen::LLT<Matrix> llt(gram);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("admissible_rigid_modes: the mass matrix is singular on the rigid motions");
  return llt.matrixU().solve<Eigen::OnTheRight>(modes);
}

std::vector<std::string> unconstrained_rigid_motions(const Mesh& mesh,
                                                     const std::vector<int>& constrained_dofs) {
  const int dim = mesh.dim();
  const int modes = dim == 3 ? 6 : 3;
  const Eigen::RowVectorXd lo = mesh.rest_positions.colwise().minCoeff(),
                           hi = mesh.rest_positions.colwise().maxCoeff();
  const Eigen::RowVectorXd centre = 0.5 * (lo + hi);
  const double scale = std::max((hi - lo).norm(), std::numeric_limits<double>::min());
  // Columns: translations, then rotations about the bounding-box centre (e_a x X).
  Matrix R = Matrix::Zero(static_cast<Eigen::Index>(constrained_dofs.size()), modes);
  for (std::size_t i = 0; i < constrained_dofs.size(); ++i) {
    const int v = constrained_dofs[i] / dim, k = constrained_dofs[i] % dim;
    if (constrained_dofs[i] < 0 || v >= mesh.num_vertices())
      throw std::invalid_argument("unconstrained_rigid_motions: DOF " + std::to_string(constrained_dofs[i]) +
                                  " is not a DOF of the mesh's " + std::to_string(mesh.num_vertices()) +
                                  " vertices");
    const Eigen::RowVectorXd X = (mesh.rest_positions.row(v) - centre) / scale;
    const auto row = static_cast<Eigen::Index>(i);
    R(row, k) = 1.0;
    if (dim == 2) {
      R(row, 2) = k == 0 ? -X[1] : X[0];  // e_z x X
    } else {
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        R(row, 3 + a) = k == c ? X[b] : (k == b ? -X[c] : 0.0);
      }
    }
  }
  const Vector values = symmetric_eigenvalues(R.transpose() * R);
  const double largest = std::max(values.maxCoeff(), 0.0);
  const char* const names[6] = {"translation along x", "translation along y", "translation along z",
                                "rotation about x",    "rotation about y",    "rotation about z"};
  auto name = [&](int j) { return names[dim == 2 && j == 2 ? 5 : j]; };
  int free_count = 0;
  for (Eigen::Index i = 0; i < values.size(); ++i)
    if (!(values[i] > 1e-10 * largest) || largest == 0.0) ++free_count;
  // Name the coordinate motions that leave every constrained DOF in place; the rest of the
  // free space (e.g. rotations about a pinned vertex rather than the box centre) is counted.
  std::vector<std::string> free;
  for (int j = 0; j < modes && static_cast<int>(free.size()) < free_count; ++j)
    if (!(R.col(j).squaredNorm() > 1e-10 * largest) || largest == 0.0) free.emplace_back(name(j));
  while (static_cast<int>(free.size()) < free_count)
    free.emplace_back("a rigid motion combining translation and rotation");
  return free;
}

}  // namespace tailor
