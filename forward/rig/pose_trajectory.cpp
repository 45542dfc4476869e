#include "forward/rig/pose_trajectory.hpp"

#include <algorithm>
#include <stdexcept>

namespace tailor {

PoseTrajectory::PoseTrajectory(std::vector<double> times, std::vector<Vector> poses)
    : times_(std::move(times)), poses_(std::move(poses)) {
  if (times_.empty() || times_.size() != poses_.size())
    throw std::invalid_argument("pose trajectory: needs as many keyframe times as poses, at least one");
  for (std::size_t k = 1; k < times_.size(); ++k) {
    if (!(times_[k] > times_[k - 1])) throw std::invalid_argument("pose trajectory: times must increase");
    if (poses_[k].size() != poses_[0].size()) throw std::invalid_argument("pose trajectory: poses of different sizes");
  }
  const std::size_t n = times_.size();
  tangents_.assign(n, Vector::Zero(poses_[0].size()));
  for (std::size_t k = 1; k + 1 < n; ++k)
    tangents_[k] = (poses_[k + 1] - poses_[k - 1]) / (times_[k + 1] - times_[k - 1]);
}

PoseTrajectory::PoseTrajectory(std::function<PoseMotion(double)> motion) : motion_(std::move(motion)) {
  if (!motion_) throw std::invalid_argument("pose trajectory: empty motion");
}

PoseMotion PoseTrajectory::operator()(double t) const {
  if (motion_) return motion_(t);
  PoseMotion m;
  const int size = static_cast<int>(poses_[0].size());
  m.velocity = m.acceleration = Vector::Zero(size);
  if (t <= times_.front() || times_.size() == 1) {
    m.p = poses_.front();
    return m;
  }
  if (t >= times_.back()) {
    m.p = poses_.back();
    return m;
  }
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
  const double h = times_[k + 1] - times_[k], s = (t - times_[k]) / h;
  // Hermite basis and its derivatives in s.
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
  const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  const double d00 = 6 * s * s - 6 * s, d10 = 3 * s * s - 4 * s + 1, d01 = -d00, d11 = 3 * s * s - 2 * s;
  const double e00 = 12 * s - 6, e10 = 6 * s - 4, e01 = -e00, e11 = 6 * s - 2;
  const Vector &p0 = poses_[k], &p1 = poses_[k + 1], &m0 = tangents_[k], &m1 = tangents_[k + 1];
  m.p = h00 * p0 + h10 * h * m0 + h01 * p1 + h11 * h * m1;
  m.velocity = (d00 * p0 + d10 * h * m0 + d01 * p1 + d11 * h * m1) / h;
  m.acceleration = (e00 * p0 + e10 * h * m0 + e01 * p1 + e11 * h * m1) / (h * h);
  return m;
}

}  // namespace tailor
