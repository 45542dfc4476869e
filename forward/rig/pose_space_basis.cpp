#include "forward/rig/pose_space_basis.hpp"

#include <Eigen/Cholesky>
#include <set>
#include <stdexcept>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/reduction/constrained_modes.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {
namespace {

SparseMatrix restrict_to(const SparseMatrix& full, const std::vector<int>& free_index, int nf) {
  Triplets t;
  for (int col = 0; col < full.outerSize(); ++col)
    for (SparseMatrix::InnerIterator e(full, col); e; ++e) {
      const int a = free_index[static_cast<std::size_t>(e.row())], b = free_index[static_cast<std::size_t>(e.col())];
      if (a >= 0 && b >= 0) t.emplace_back(a, b, e.value());
    }
  SparseMatrix out(nf, nf);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

}  // namespace

Matrix procrustes_rotation(const Matrix& basis, const Matrix& reference, const SparseMatrix& mass) {
  if (basis.rows() != reference.rows() || basis.cols() != reference.cols() || mass.rows() != basis.rows())
    throw std::invalid_argument("procrustes: bases of different sizes");
  const Matrix cross = basis.transpose() * (mass * reference);
  const SingularValueDecomposition svd = singular_value_decomposition(cross, true, true);
  return svd.U * svd.V.transpose();
}

Matrix example_pose_basis(const Rig& rig, const RiggedBody& body, const Vector& pose, const SparseMatrix& mass,
                          const Matrix& contact_constraints, const ExamplePoseBasisOptions& options) {
  if (body.fixed_vertices.empty())
    throw std::invalid_argument("pose-space basis: the body needs a region fixed to the rig");
  if (options.linear_modes < 1 || options.derivative_modes < 0 || options.derivative_modes > options.linear_modes ||
      options.size < 1)
    throw std::invalid_argument("pose-space basis: bad mode counts");
  const Vector rest = rig.rest_shape(pose);
  const Model model = rigged_elastic_model(body, rest);
  const Vector params = rigged_body_parameters(body);
  const int n = static_cast<int>(rest.size());
  const std::vector<int> free = rigged_free_dofs(body);
  const int nf = static_cast<int>(free.size());
  std::vector<int> free_index(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < nf; ++k) free_index[static_cast<std::size_t>(free[k])] = k;

  const SparseMatrix k_free = restrict_to(model.terms().front()->hessian(rest, params, HessianMode::exact), free_index, nf);
  const SparseMatrix m_free = restrict_to(mass, free_index, nf);
  Matrix c_free = Matrix::Zero(contact_constraints.rows(), nf);
  if (contact_constraints.rows() > 0) {
    if (contact_constraints.cols() != n) throw std::invalid_argument("pose-space basis: constraints must be m x 3n");
    for (int k = 0; k < nf; ++k) c_free.col(k) = contact_constraints.col(free[k]);
  }
  const ConstrainedModes modes = constrained_modes(k_free, m_free, c_free, options.linear_modes);
  auto expand = [&](const Vector& y) {
    Vector full = Vector::Zero(n);
    for (int k = 0; k < nf; ++k) full[free[k]] = y[k];
    return full;
  };

  // Static responses N (N^T K N)^-1 N^T f to loads f (n x k), the stiffness factored once.
  SparseMatrix null_space;
  SparseCholesky cholesky;
  bool factored = false;
  auto static_responses = [&](const Matrix& load) {
    if (!factored) {
      null_space = constraint_null_space(c_free);
      const SparseMatrix projected = SparseMatrix(null_space.transpose() * k_free * null_space);
      const FactorizationResult fr = cholesky.factorize(SparseMatrix(projected.triangularView<Eigen::Upper>()));
      if (!fr.success) throw std::runtime_error("pose-space basis: stiffness factorization failed: " + fr.message);
      factored = true;
    }
    Matrix load_free(nf, load.cols());
    for (int k = 0; k < nf; ++k) load_free.row(k) = load.row(free[k]);
    const Matrix z = cholesky.solve_columns(null_space.transpose() * load_free);
    std::vector<Vector> out;
    for (int col = 0; col < z.cols(); ++col) out.push_back(expand(null_space * z.col(col)));
    return out;
  };

  std::vector<Vector> candidates, derivatives;
  if (options.motion_responses) {
    // The rig's own inertial loads at this pose: d2X/dt2 = J p'' + sum_kl d2X/dp_k dp_l p'_k p'_l,
    // so the loads M dX/dp_k and M d2X/dp_k dp_l (and gravity's M g) span -M d2X/dt2 + M g for
    // every rig motion through the pose; their static responses come first (a few columns that
    // carry most of the quasi-static jiggle).
    const int np = rig.num_parameters();
    Matrix loads(n, np + np * (np + 1) / 2 + (body.gravity.norm() > 0.0 ? 1 : 0));
    const Matrix jacobian = rig.rest_shape_jacobian(pose);
    int col = 0;
    for (int k = 0; k < np; ++k) loads.col(col++) = mass * jacobian.col(k);
    for (int k = 0; k < np; ++k)
      for (int l = k; l < np; ++l) loads.col(col++) = mass * rig.rest_shape_second(pose, Vector::Unit(np, k), Vector::Unit(np, l));
    if (body.gravity.norm() > 0.0) {
      Vector g(n);
      for (int v = 0; v < n / 3; ++v) g.segment<3>(3 * v) = body.gravity;
      loads.col(col++) = mass * g;
    }
    for (Vector& r : static_responses(loads))
      if (r.norm() > 0.0) candidates.push_back(std::move(r));
  }
  for (int i = 0; i < options.linear_modes; ++i) candidates.push_back(expand(modes.modes.col(i)));
  if (options.derivative_modes > 0) {
    // Modal derivatives under the constraints: psi_ij = -N (N^T K N)^-1 N^T H(phi_i) phi_j
    // (Barbic & James 2005, eq. 9, restricted to null(C)).
    double extent = 0.0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::ArrayXd coordinate = Eigen::Map<const Eigen::ArrayXd, 0, Eigen::InnerStride<3>>(rest.data() + c, n / 3);
      extent = std::max(extent, coordinate.maxCoeff() - coordinate.minCoeff());
    }
    const int first_mode = static_cast<int>(candidates.size()) - options.linear_modes;
    Matrix hessian_products(n, options.derivative_modes * (options.derivative_modes + 1) / 2);
    int col = 0;
    for (int i = 0; i < options.derivative_modes; ++i)
      for (int j = i; j < options.derivative_modes; ++j)
        hessian_products.col(col++) =
            -stiffness_directional_derivative(model, rest, params, candidates[static_cast<std::size_t>(first_mode + i)],
                                              candidates[static_cast<std::size_t>(first_mode + j)], 1e-3 * extent);
    derivatives = static_responses(hessian_products);
  }
  if (options.inertial_responses) {
    // Quasi-static responses to any bone acceleration: f_inert = -M sum_b B_b vec12(T_b''), so
    // N (N^T K N)^-1 N^T M B_b spans the static response to every bone motion.
    for (int b = 0; b < rig.num_bones(); ++b)
      for (Vector& r : static_responses(Matrix(mass * rig.skinning_basis(b)))) candidates.push_back(std::move(r));
  }
  candidates.insert(candidates.end(), derivatives.begin(), derivatives.end());
  Matrix stacked(n, static_cast<int>(candidates.size()));
  for (std::size_t k = 0; k < candidates.size(); ++k) stacked.col(static_cast<int>(k)) = candidates[k];
  const Matrix basis = mass_orthonormal_basis(stacked, mass);
  if (basis.cols() < options.size)
    throw std::invalid_argument("pose-space basis: only " + std::to_string(basis.cols()) +
                                " independent candidates for r = " + std::to_string(options.size));
  return basis.leftCols(options.size);
}

Matrix contact_constraints_at(const Rig& rig, const Vector& pose, const std::vector<int>& surface_vertices,
                              double distance) {
  const Vector x = rig.rest_shape(pose);
  const int n = rig.num_vertices();
  auto bone_of = [&](int v) {
    int best = 0;
    rig.weights().row(v).maxCoeff(&best);
    return best;
  };
  std::set<std::pair<int, int>> pairs;  // each pair once
  for (int a : surface_vertices) {
    int nearest = -1;
    double best = distance;
    for (int b : surface_vertices) {
      if (b == a || bone_of(b) == bone_of(a)) continue;
      // Neighbours in the bind pose are not contacts: only pairs the pose brought together.
      if ((rig.rest_positions().row(a) - rig.rest_positions().row(b)).norm() <= 2.0 * distance) continue;
      const double d = (x.segment<3>(3 * a) - x.segment<3>(3 * b)).norm();
      if (d < best) best = d, nearest = b;
    }
    if (nearest >= 0) pairs.emplace(std::min(a, nearest), std::max(a, nearest));
  }
  std::vector<Eigen::RowVectorXd> rows;
  for (const auto& [a, b] : pairs) {
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(3 * n);
    Eigen::Vector3d normal = x.segment<3>(3 * a) - x.segment<3>(3 * b);
    normal /= std::max(normal.norm(), 1e-300);
    row.segment<3>(3 * a) = normal.transpose();
    row.segment<3>(3 * b) = -normal.transpose();
    rows.push_back(row);
  }
  Matrix c(static_cast<int>(rows.size()), 3 * n);
  for (std::size_t k = 0; k < rows.size(); ++k) c.row(static_cast<int>(k)) = rows[k];
  return c;
}

PoseSpaceBasis::PoseSpaceBasis(std::vector<Matrix> bases, const SparseMatrix& mass) {
  if (bases.empty()) throw std::invalid_argument("pose-space basis: no example pose");
  for (const Matrix& b : bases)
    if (b.rows() != bases.front().rows() || b.cols() != bases.front().cols())
      throw std::invalid_argument("pose-space basis: bases of different sizes");
  for (const Matrix& b : bases) {
    rotations_.push_back(procrustes_rotation(b, bases.front(), mass));
    aligned_.push_back(b * rotations_.back());
  }
  const int m = poses();
  std::vector<Matrix> mass_times(static_cast<std::size_t>(m));
  for (int j = 0; j < m; ++j) mass_times[static_cast<std::size_t>(j)] = mass * aligned_[static_cast<std::size_t>(j)];
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      gram_.push_back(aligned_[static_cast<std::size_t>(i)].transpose() * mass_times[static_cast<std::size_t>(j)]);
}

Matrix PoseSpaceBasis::orthonormalizer(const Vector& w) const {
  const int m = poses(), r = size();
  Matrix g = Matrix::Zero(r, r);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      if (w[i] != 0.0 && w[j] != 0.0) g += (w[i] * w[j]) * gram(i, j);
  const Eigen::LLT<Matrix> llt(g);
  if (llt.info() != Eigen::Success) throw std::runtime_error("pose-space basis: the blended basis is rank deficient");
  // L^-T = (L^-1)^T
  Matrix inverse = Matrix::Identity(r, r);
  llt.matrixL().solveInPlace(inverse);
  return inverse.transpose();
}

Matrix PoseSpaceBasis::blend(const Vector& w) const {
  Matrix u = Matrix::Zero(aligned_.front().rows(), size());
  for (int i = 0; i < poses(); ++i)
    if (w[i] != 0.0) u += w[i] * aligned_[static_cast<std::size_t>(i)];
  return u * orthonormalizer(w);
}

}  // namespace tailor
