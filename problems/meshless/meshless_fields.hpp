#pragma once
// The result fields of a meshless solid at a state, as arrays (what nodes.vtu and samples.vtu
// hold; Python's simulate() and MeshlessFunctional.fields(z)), and the map from the node
// coefficients to the MLS field's values at the nodes. MLS shape functions do not interpolate
// (phi_a(X_b) != delta_ab): the DOFs x_a are coefficients, and the displacement at a node is
// u(X_b) = sum_a phi_a(X_b) (x_a - X_a), not x_b - X_b.
#include <Eigen/Core>

#include "forward/core/types.hpp"
#include "problems/meshless/meshless_scene.hpp"

namespace tailor {

struct MeshlessFields {
  Eigen::MatrixXd rest_positions;            // nodes x 3: X_a
  Eigen::MatrixXd displacement;              // nodes x 3: the MLS field's displacement u(X_a) at the nodes
  Eigen::MatrixXd positions;                 // nodes x 3: X_a + u(X_a)
  Eigen::MatrixXd coefficient_displacement;  // nodes x 3: x_a - X_a (the DOFs less the rest state)
  Eigen::MatrixXd samples;                   // samples x 3: the output points (surface samples, else quadrature points)
  Eigen::MatrixXd sample_displacement;       // samples x 3: u at the samples
  Eigen::VectorXd youngs_modulus;            // per node: E_a (the parameters' first block)
};

// Interleaved 3n x 3n: (N u_coef)[3b + k] = sum_a phi_a(X_b) u_coef[3a + k], the field's values
// at the nodes from the coefficient displacements (or positions: N reproduces X). SceneError
// naming the node where the shape functions do not exist.
SparseMatrix meshless_node_values(const MeshlessScene& S);

// The MLS field's displacement at the samples, interleaved (3 per sample), at the state x.
Eigen::VectorXd meshless_sample_displacements(const MeshlessScene& S, const Vector& x);

// The fields at the state x (3n coefficients) and parameters p ([E per node, nu per node]);
// node_values from meshless_node_values(S).
MeshlessFields meshless_fields(const MeshlessScene& S, const SparseMatrix& node_values, const Vector& x,
                               const Vector& p);

// An interleaved vector of 3 m entries as m x 3 rows, and back.
Eigen::MatrixXd as_point_rows(const Vector& interleaved);
Vector as_interleaved(const Eigen::MatrixXd& rows);

}  // namespace tailor
