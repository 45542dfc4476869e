#pragma once
// Reduced dynamics on the moving rest shape with pose-space bases (Xu & Barbic 2016, sections
// 4-5): u = U(p) q with U(p) the blended, re-orthonormalized basis (pose_space_basis.hpp), and
//
//   q'' + alpha q' + U^T f_int(X(p); X(p) + U q) = U^T (f_ext - M d2X/dt2),
//
// the basis's rate of change neglected as in the paper. Nothing per step is proportional to the
// mesh:
//  - internal forces by cubature (An, Kim & James 2008): a rule (elements, weights) is fitted
//    per example pose i on the forces of its rest shape X(p_i) and basis U_i (training error
//    reported); at run time the rules are blended, omega_e(p) = sum_i w_i(p) omega_e^i, and each
//    rule element is evaluated on the current rest shape (its 4 vertices skinned) with the
//    current basis rows: force U_e^T f_e, stiffness U_e^T K_e U_e, O(|C| r^2);
//  - inertial and gravity forces from precomputed projections: X is linear in the bone
//    transforms and correction weights (Rig::skinning_basis), so
//    U_i^T M d2X/dt2 = sum_b (U_i^T M B_b) vec12(d2T_b/dt2) + sum_k (U_i^T M delta_k) d2w_k/dt2.
// Time stepping: implicit Euler in q with dense Newton (max_newton_iterations = 1 is the
// linearly implicit scheme of Barbic & James 2005).
#include <string>
#include <vector>

#include "forward/reduction/cubature.hpp"
#include "forward/rig/pose_space_basis.hpp"

namespace tailor {

struct ExamplePose {
  Vector pose;
  Matrix contact_constraints;  // m x 3n bilateral constraints at this pose (empty: none)
};

struct PoseSpaceOptions {
  ExamplePoseBasisOptions basis;
  CubatureOptions cubature;          // per example pose
  int training_poses = 30;           // random reduced poses per example pose
  double training_displacement = 0.0;  // their largest vertex displacement [length]; 0: 5% of the body's extent
  unsigned seed = 1;
};

struct ExamplePosePrecomputation {
  double basis_seconds = 0.0, cubature_seconds = 0.0;
  int cubature_elements = 0;
  double training_error = 0.0;
  int contact_constraints = 0;
};

struct ReducedRigState {
  double time = 0.0;
  Vector q, v;
};

class PoseSpaceDynamics {
 public:
  // The body, rig and dynamics options as for MovingRestDynamics (gravity, damping, inertial
  // forces, time step, Newton settings). Throws as example_pose_basis / fit_cubature do.
  PoseSpaceDynamics(const Rig& rig, const RiggedBody& body, std::vector<ExamplePose> examples,
                    const PoseSpaceOptions& options, const MovingRestOptions& dynamics);

  int size() const { return basis_.size(); }
  const PoseSpaceBasis& basis() const { return basis_; }
  const std::vector<ExamplePosePrecomputation>& precomputation() const { return precomputation_; }
  int cubature_elements() const { return static_cast<int>(elements_.size()); }  // union over poses

  ReducedRigState initial_state(double time = 0.0) const;
  bool step(const PoseTrajectory& trajectory, const ReducedRigState& current, ReducedRigState& next,
            int& iterations, std::string& message) const;
  // u = U(p) q in full space (3n), for output and comparisons (O(n r m)).
  Vector displacement(const Vector& p, const Vector& q) const;
  // Pose weights of the example poses at p.
  Vector weights(const Vector& p) const;

 private:
  struct RuleElement {
    Eigen::Vector4i vertices;      // mesh vertices
    Eigen::Vector4i local;         // their indices into skinned_vertices_
    Eigen::VectorXd weights;       // omega_e^i per example pose
    double lambda = 0.0, mu = 0.0;
    std::vector<Eigen::Matrix<double, 12, Eigen::Dynamic>> rows;  // aligned U_i rows per pose
  };
  const Rig& rig_;
  std::vector<Vector> poses_;
  std::vector<ExamplePosePrecomputation> precomputation_;  // before basis_: build_bases fills it
  PoseSpaceBasis basis_;
  MovingRestOptions dynamics_;
  std::shared_ptr<const Material<3>> material_;
  std::vector<RuleElement> elements_;
  std::vector<int> skinned_vertices_;
  std::vector<Matrix> bone_projection_;    // per pose: r x 12 bones, (U_i^T M B_b)
  std::vector<Matrix> correction_projection_;  // per pose: r x corrections
  std::vector<Vector> gravity_projection_;     // per pose: U_i^T M g

  static PoseSpaceBasis build_bases(const Rig& rig, const RiggedBody& body, const std::vector<ExamplePose>& examples,
                                    const PoseSpaceOptions& options, const SparseMatrix& mass,
                                    std::vector<ExamplePosePrecomputation>& precomputation);
};

}  // namespace tailor
