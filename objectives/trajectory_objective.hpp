#pragma once
// Objectives on trajectories of a time-dependent simulation:
//   J = sum_n J_n(x_n, v_n, p),  n = 0 (the initial state) ... N (the final state),
// x_n positions and v_n velocities after step n (full DOF space, interleaved), p the model
// parameters. The time-dependent adjoint (adjoint/transient_functional.hpp) needs each J_n
// and its partial derivatives in x_n, v_n and p.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

class TrajectoryObjective {
 public:
  virtual ~TrajectoryObjective() = default;
  virtual std::string name() const = 0;
  // J_n; steps the objective does not look at contribute 0.
  virtual double value(int step, const Vector& x, const Vector& v, const Vector& p) const = 0;
  // gx += dJ_n/dx_n, gv += dJ_n/dv_n, gp += dJ_n/dp.
  virtual void add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx,
                            Vector& gv, Vector& gp) const = 0;
};

using TrajectoryObjectivePtr = std::shared_ptr<const TrajectoryObjective>;

// Targets for chosen vertices at chosen steps (keyframes):
//   J_n = w_k / 2 sum_i |q_{v_i}(n) - target_k(i)|^2   when step n is keyframe k,
// q the positions or the velocities of the vertices. A target at every step is a keyframe per
// step; a final-state target is one keyframe at the last step.
enum class TrajectoryQuantity { position, velocity };

struct Keyframe {
  int step;
  Matrix targets;  // |vertices| x dim
  double weight = 1.0;
};

class KeyframeTargets final : public TrajectoryObjective {
 public:
  // Throws std::invalid_argument on a negative step, a repeated step, or a target matrix of the
  // wrong shape.
  KeyframeTargets(int dim, std::vector<int> vertices, TrajectoryQuantity quantity,
                  std::vector<Keyframe> keyframes);
  std::string name() const override;
  double value(int step, const Vector& x, const Vector& v, const Vector& p) const override;
  void add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx, Vector& gv,
                    Vector& gp) const override;

 private:
  const Keyframe* find(int step) const;
  int dim_;
  std::vector<int> vertices_;
  TrajectoryQuantity quantity_;
  std::vector<Keyframe> keyframes_;  // sorted by step
};

// Per-mode amplitudes: the mass-weighted projection of the displacement on given modes,
//   a_n = Phi^T M (x_n - X)   (Phi: n x r mode shapes, M a fixed mass matrix, X rest positions),
//   J_n = w_k / 2 |a_n - target_k|^2   at keyframe steps (targets of size r).
struct AmplitudeKeyframe {
  int step;
  Vector targets;  // one per mode
  double weight = 1.0;
};

class ModeAmplitudes final : public TrajectoryObjective {
 public:
  ModeAmplitudes(Matrix modes, const SparseMatrix& mass, Vector rest,
                 std::vector<AmplitudeKeyframe> keyframes);
  std::string name() const override { return "mode_amplitudes"; }
  double value(int step, const Vector& x, const Vector& v, const Vector& p) const override;
  void add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx, Vector& gv,
                    Vector& gp) const override;
  Vector amplitudes(const Vector& x) const;  // a = Phi^T M (x - X)

 private:
  const AmplitudeKeyframe* find(int step) const;
  Matrix weighted_modes_;  // M Phi
  Vector rest_;
  std::vector<AmplitudeKeyframe> keyframes_;
};

// A linear functional of the positions: J_n = w_n . x_n, with one weight vector per step
// (full DOF space, interleaved, as x_n), n = 0 ... N. Its design gradient is the vector-Jacobian
// product of the trajectory with the cotangents w_n (TransientFunctional::objective_gradient).
class PositionCotangents final : public TrajectoryObjective {
 public:
  // weights: (N + 1) rows (one per state), num_dofs columns. Throws std::invalid_argument for
  // non-finite entries.
  explicit PositionCotangents(Matrix weights);
  std::string name() const override { return "position_cotangents"; }
  double value(int step, const Vector& x, const Vector& v, const Vector& p) const override;
  void add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx, Vector& gv,
                    Vector& gp) const override;

 private:
  Matrix weights_;
};

// A weighted sum of trajectory objectives.
class TrajectorySum final : public TrajectoryObjective {
 public:
  void add(TrajectoryObjectivePtr objective, double weight = 1.0);
  std::string name() const override;
  double value(int step, const Vector& x, const Vector& v, const Vector& p) const override;
  void add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx, Vector& gv,
                    Vector& gp) const override;

 private:
  std::vector<std::pair<TrajectoryObjectivePtr, double>> terms_;
};

}  // namespace tailor
