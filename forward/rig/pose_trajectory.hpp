#pragma once
// A keyframed rig trajectory p(t): piecewise cubic Hermite through keyframes (t_k, p_k) with
// Catmull-Rom tangents (p_{k+1} - p_{k-1}) / (t_{k+1} - t_{k-1}) inside and zero tangents at the
// first and last keyframe; constant before the first and after the last. p is C1 and its second
// derivative is exact within each segment (piecewise linear), which is what the inertial forces
// -M d2X/dt2 of the moving rest shape read. Time in seconds, p in the rig's units.
#include <functional>
#include <vector>

#include "forward/rig/rig.hpp"

namespace tailor {

class PoseTrajectory {
 public:
  // Keyframe times strictly increasing, poses all of one size; std::invalid_argument otherwise.
  PoseTrajectory(std::vector<double> times, std::vector<Vector> poses);
  // Any motion given by a function (closed forms in tests: constant acceleration, spinning).
  explicit PoseTrajectory(std::function<PoseMotion(double)> motion);

  PoseMotion operator()(double t) const;
  double end_time() const { return times_.empty() ? 0.0 : times_.back(); }

 private:
  std::vector<double> times_;
  std::vector<Vector> poses_, tangents_;
  std::function<PoseMotion(double)> motion_;
};

}  // namespace tailor
