#pragma once
// Basic types shared by every layer of tailor.
//
// Conventions: a state vector x holds world positions (not displacements) of all vertices,
// interleaved by vertex: x[dim * v + k]. A parameter vector p is one flat vector; each energy
// term knows which slice it reads (see ParameterLayout in model.hpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <utility>
#include <vector>

namespace tailor {

using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Triplet = Eigen::Triplet<double, int>;
using Triplets = std::vector<Triplet>;

// One (row, col) slot of a Hessian sparsity pattern, in DOF indices.
struct HessianEntry {
  int row;
  int col;
};
using HessianPattern = std::vector<HessianEntry>;

// How second derivatives of an energy are requested.
//  exact:     the true Hessian (used by the adjoint; may be indefinite).
//  projected: each element's Hessian made positive semidefinite (used by Newton to make
//             progress far from equilibrium).
enum class HessianMode { exact, projected };

}  // namespace tailor
