#pragma once
// Essential (Dirichlet) conditions for non-interpolating MLS shape functions
// (docs/meshless.md, "Boundary conditions"). The DOFs are nodal coefficients, not values:
// x(X) = sum_a phi_a(X) x_a, and phi_a(X_b) != delta_ab, so fixing x_b = target ("the naive
// way") does not make x(X_b) = target.
//
// Transformation (collocation) method: the constraints x(X_b) = t_b at the rest positions X_b
// of the constrained nodes b in B are the linear equations
//   C_BB x_B + C_BO x_O = t,  C_ba = phi_a(X_b),
// one per component. With C_BB invertible they are solved for the constrained coefficients,
//   x_B = C_BB^-1 (t - C_BO x_O),
// and the others stay free: x = x0 + S y with y = x_O, an Elimination that the Model, Newton and
// the adjoint take as they take Dirichlet conditions. The conditions then hold exactly (to
// round-off) at the collocation points X_b; between them the field is the MLS field of the
// coefficients, not the prescribed one. The rows of S for B are dense over the free nodes
// whose supports reach a collocation point.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "forward/core/elimination.hpp"
#include "forward/meshless/mls_shape_functions.hpp"

namespace tailor {

struct MlsEssentialConditions {
  Elimination elimination;
  double condition_estimate;  // the largest over the components  // 1 / (reciprocal condition estimate of C_BB)
};

// Conditions on one component k: x_k(X_b) = targets[i] at the rest positions of nodes[i].
struct MlsComponentConditions {
  std::vector<int> nodes;
  Eigen::VectorXd targets;
};

// Per component (symmetry planes hold one component, a clamp all three): each component's
// constrained coefficients are eliminated by its own C_BB; the free unknowns y are the other
// (node, component) coefficients in increasing DOF order. std::invalid_argument on a repeated
// or out-of-range node, sizes that differ, or when a C_BB is singular or its reciprocal
// condition estimate is below 1e-12 (collocation points too close for the supports).
MlsEssentialConditions mls_transformation(const MlsShapeFunctions& mls,
                                          const std::array<MlsComponentConditions, 3>& components);

// All three components at the listed nodes; targets: |nodes| x 3 prescribed positions x(X_b).
MlsEssentialConditions mls_transformation(const MlsShapeFunctions& mls, const std::vector<int>& nodes,
                                          const Eigen::MatrixXd& targets);

}  // namespace tailor
