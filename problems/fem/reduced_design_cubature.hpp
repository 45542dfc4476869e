#pragma once
// The cubature rule of the reduced design loop (problems/fem/reduced_design.hpp) for materials
// whose reduced energy has no precomputed polynomial (Neo-Hookean, corotated, ...): training
// poses from the handle responses, the greedy NNLS fit of forward/reduction/cubature.hpp over
// the base material and every material mode, and the CubatureDesignModel of the rule.
//
// Training poses (An, Kim, James 2008 train on poses of the expected deformations): with
// K(w) = Phi^T K(x_rest; E0 (1 + Y w)) Phi the reduced stiffness at rest and f the reduced
// handle load, the linear response q_0 = K(0)^-1 f at 1/2, 1 and 3/2 of the load, the linear
// responses K(+-w_j)^-1 f of designs softened or stiffened along each mode (w_j = 1/2 e_j where
// K stays positive definite), then random poses t q_0 + d, t in [0, 3/2], d a random direction
// of up to half q_0's largest displacement. A pose with an element the material cannot
// evaluate (inverted) is halved until it can.
#include <memory>

#include "forward/core/model.hpp"
#include "forward/reduction/cubature_design_model.hpp"
#include "problems/fem/inverse_scene.hpp"

namespace tailor {

struct ReducedDesignCubature {
  int elements = 0;             // |C|
  int mesh_elements = 0;        // what the rule stands in for
  int training_poses = 0;       // fitted on
  double training_error = 0.0;  // |A omega - b| / |b| over the training forces
  double seconds = 0.0;
  bool exact = false;  // elements >= the mesh's: every element at weight 1, no fit
};

// model: its elastic terms (E0 in p); basis: num_dofs x r; material_modes: num_elements x m;
// load: the reduced load Phi^T f (r). Throws std::invalid_argument (prefixed by `key`) when
// the rule cannot be fitted (no usable pose, a material not linear in Young's modulus).
std::shared_ptr<const CubatureDesignModel> fit_reduced_design_cubature(
    const Model& model, const Vector& p, const Matrix& basis, const Matrix& material_modes,
    const Vector& load, const CubatureSpec& spec, const std::string& key, ReducedDesignCubature& summary);

}  // namespace tailor
