#pragma once
// Operators of a Model restricted to its free unknowns y (x = x0 + S y, see elimination.hpp):
// the stiffness K_y = S^T (d2E/dx2) S and the mass M_y = S^T M S, as full symmetric sparse
// matrices, and the rigid-body motions of the body that the constraints leave free.
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

// Exact stiffness S^T H(x) S at the full state x [energy / length^2], both triangles.
SparseMatrix free_stiffness(const Model& model, const Vector& x, const Vector& p);
// S^T M S for a full-space mass matrix M (num_dofs^2).
SparseMatrix free_mass(const Model& model, const SparseMatrix& mass);

// The infinitesimal rigid-body motions of the vertices at positions x (interleaved, dimension
// dim): dim translations and dim (dim - 1) / 2 rotations about the centroid, num_dofs x
// (3 or 6), not normalized.
Matrix rigid_body_motions(const Vector& x, int dim);

// The rigid motions the model's constraints admit (r = S y for some y), expressed in the free
// unknowns y and M_y-orthonormal: a basis of {y : S y is rigid}, num_free x k, k in [0, 6].
// A body clamped anywhere gets k = 0; a free body k = 3 (2D) or 6 (3D); a body pinned at one
// point k = 1 (2D) or 3 (3D).
Matrix admissible_rigid_modes(const Model& model, const Vector& x, int dim,
                              const SparseMatrix& free_mass_matrix);

// The rigid motions of the mesh at rest that leave every listed DOF (dim * vertex + component)
// in place, one description per independent motion ("translation along x", "rotation about
// z", or "a rigid motion combining ..."); empty when the DOFs pin the body. The test: the
// rigid motions restricted to the DOFs (lengths scaled by the bounding-box diagonal) are
// linearly independent.
std::vector<std::string> unconstrained_rigid_motions(const Mesh& mesh, const std::vector<int>& constrained_dofs);

}  // namespace tailor
