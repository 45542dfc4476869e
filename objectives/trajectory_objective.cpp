#include "objectives/trajectory_objective.hpp"

#include <algorithm>
#include <stdexcept>

namespace tailor {
namespace {

template <class Frame>
void sort_and_check(std::vector<Frame>& frames, const std::string& who) {
  std::sort(frames.begin(), frames.end(), [](const Frame& a, const Frame& b) { return a.step < b.step; });
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (frames[k].step < 0)
      throw std::invalid_argument(who + ": keyframe step " + std::to_string(frames[k].step) + " < 0");
    if (k > 0 && frames[k].step == frames[k - 1].step)
      throw std::invalid_argument(who + ": step " + std::to_string(frames[k].step) + " has two keyframes");
  }
}

template <class Frame>
const Frame* find_step(const std::vector<Frame>& frames, int step) {
  const auto it =
      std::lower_bound(frames.begin(), frames.end(), step, [](const Frame& f, int s) { return f.step < s; });
  return it != frames.end() && it->step == step ? &*it : nullptr;
}

}  // namespace

KeyframeTargets::KeyframeTargets(int dim, std::vector<int> vertices, TrajectoryQuantity quantity,
                                 std::vector<Keyframe> keyframes)
    : dim_(dim), vertices_(std::move(vertices)), quantity_(quantity), keyframes_(std::move(keyframes)) {
  sort_and_check(keyframes_, "KeyframeTargets");
  for (const Keyframe& k : keyframes_)
    if (k.targets.rows() != static_cast<int>(vertices_.size()) || k.targets.cols() != dim_)
      throw std::invalid_argument("KeyframeTargets: the targets of step " + std::to_string(k.step) + " are " +
                                  std::to_string(k.targets.rows()) + " x " +
                                  std::to_string(k.targets.cols()) + ", expected " +
                                  std::to_string(vertices_.size()) + " x " + std::to_string(dim_));
  for (int v : vertices_)
    if (v < 0) throw std::invalid_argument("KeyframeTargets: negative vertex index");
}

std::string KeyframeTargets::name() const {
  return quantity_ == TrajectoryQuantity::position ? "keyframe_positions" : "keyframe_velocities";
}

const Keyframe* KeyframeTargets::find(int step) const { return find_step(keyframes_, step); }

double KeyframeTargets::value(int step, const Vector& x, const Vector& v, const Vector& p) const {
  (void)p;
  const Keyframe* k = find(step);
  if (!k) return 0.0;
  const Vector& q = quantity_ == TrajectoryQuantity::position ? x : v;
  double j = 0.0;
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    j += (q.segment(dim_ * vertices_[i], dim_) - k->targets.row(i).transpose()).squaredNorm();
  return 0.5 * k->weight * j;
}

void KeyframeTargets::add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx,
                                   Vector& gv, Vector& gp) const {
  (void)p, (void)gp;
  const Keyframe* k = find(step);
  if (!k) return;
  const bool position = quantity_ == TrajectoryQuantity::position;
  const Vector& q = position ? x : v;
  Vector& g = position ? gx : gv;
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    g.segment(dim_ * vertices_[i], dim_) +=
        k->weight * (q.segment(dim_ * vertices_[i], dim_) - k->targets.row(i).transpose());
}

ModeAmplitudes::ModeAmplitudes(Matrix modes, const SparseMatrix& mass, Vector rest,
                               std::vector<AmplitudeKeyframe> keyframes)
    : rest_(std::move(rest)), keyframes_(std::move(keyframes)) {
  if (modes.rows() != rest_.size() || mass.rows() != rest_.size() || mass.cols() != rest_.size())
    throw std::invalid_argument("ModeAmplitudes: modes, mass matrix and rest state have different sizes");
  weighted_modes_ = mass * modes;
  sort_and_check(keyframes_, "ModeAmplitudes");
  for (const AmplitudeKeyframe& k : keyframes_)
    if (k.targets.size() != modes.cols())
      throw std::invalid_argument("ModeAmplitudes: step " + std::to_string(k.step) + " has " +
                                  std::to_string(k.targets.size()) + " targets for " +
                                  std::to_string(modes.cols()) + " modes");
}

const AmplitudeKeyframe* ModeAmplitudes::find(int step) const { return find_step(keyframes_, step); }

Vector ModeAmplitudes::amplitudes(const Vector& x) const { return weighted_modes_.transpose() * (x - rest_); }

double ModeAmplitudes::value(int step, const Vector& x, const Vector& v, const Vector& p) const {
  (void)v, (void)p;
  const AmplitudeKeyframe* k = find(step);
  return k ? 0.5 * k->weight * (amplitudes(x) - k->targets).squaredNorm() : 0.0;
}

void ModeAmplitudes::add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx,
                                  Vector& gv, Vector& gp) const {
  (void)v, (void)p, (void)gv, (void)gp;
  const AmplitudeKeyframe* k = find(step);
  if (k) gx += k->weight * (weighted_modes_ * (amplitudes(x) - k->targets));
}

void TrajectorySum::add(TrajectoryObjectivePtr objective, double weight) {
  if (!objective) throw std::invalid_argument("TrajectorySum: null objective");
  terms_.emplace_back(std::move(objective), weight);
}

std::string TrajectorySum::name() const {
  std::string n = "sum(";
  for (std::size_t k = 0; k < terms_.size(); ++k) n += (k ? ", " : "") + terms_[k].first->name();
  return n + ")";
}

double TrajectorySum::value(int step, const Vector& x, const Vector& v, const Vector& p) const {
  double j = 0.0;
  for (const auto& [term, w] : terms_) j += w * term->value(step, x, v, p);
  return j;
}

void TrajectorySum::add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx,
                                 Vector& gv, Vector& gp) const {
  for (const auto& [term, w] : terms_) {
    Vector hx = Vector::Zero(gx.size()), hv = Vector::Zero(gv.size()), hp = Vector::Zero(gp.size());
    term->add_gradient(step, x, v, p, hx, hv, hp);
    gx += w * hx, gv += w * hv, gp += w * hp;
  }
}

PositionCotangents::PositionCotangents(Matrix weights) : weights_(std::move(weights)) {
  if (!weights_.allFinite())
    throw std::invalid_argument("PositionCotangents: the weights have non-finite entries");
}

double PositionCotangents::value(int step, const Vector& x, const Vector& v, const Vector& p) const {
  (void)v;
  (void)p;
  if (step < 0 || step >= weights_.rows()) return 0.0;
  return weights_.row(step).dot(x.transpose());
}

void PositionCotangents::add_gradient(int step, const Vector& x, const Vector& v, const Vector& p, Vector& gx,
                                      Vector& gv, Vector& gp) const {
  (void)x;
  (void)v;
  (void)p;
  (void)gv;
  (void)gp;
  if (step < 0 || step >= weights_.rows()) return;
  gx += weights_.row(step).transpose();
}

}  // namespace tailor
