#include "objectives/tikhonov.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor {

Tikhonov::Tikhonov(int offset, int size, double alpha, Vector prior, Vector weights)
    : offset_(offset), size_(size), alpha_(alpha), prior_(std::move(prior)), weights_(std::move(weights)) {
  const std::string who = "Tikhonov: ";
  if (offset_ < 0) throw std::invalid_argument(who + "negative parameter offset " + std::to_string(offset_));
  if (size_ < 1) throw std::invalid_argument(who + "block size must be positive, got " + std::to_string(size_));
  if (!std::isfinite(alpha_) || alpha_ < 0) throw std::invalid_argument(who + "alpha must be finite and >= 0");
  if (prior_.size() != size_)
    throw std::invalid_argument(who + "prior has " + std::to_string(prior_.size()) + " entries, block has " +
                                std::to_string(size_));
  if (!prior_.allFinite()) throw std::invalid_argument(who + "prior is not finite");
  if (weights_.size() == 0) weights_ = Vector::Ones(size_);
  if (weights_.size() != size_)
    throw std::invalid_argument(who + "weights have " + std::to_string(weights_.size()) + " entries, block has " +
                                std::to_string(size_));
  for (int i = 0; i < size_; ++i)
    if (!std::isfinite(weights_[i]) || weights_[i] < 0)
      throw std::invalid_argument(who + "weight " + std::to_string(i) + " must be finite and >= 0");
}

void Tikhonov::check_parameters(const Vector& p) const {
  if (p.size() < offset_ + size_)
    throw std::invalid_argument("Tikhonov: parameter vector of size " + std::to_string(p.size()) +
                                " does not hold the block [" + std::to_string(offset_) + ", " +
                                std::to_string(offset_ + size_) + ")");
}

double Tikhonov::value(const Vector& x, const Vector& p) const {
  (void)x;
  check_parameters(p);
  return 0.5 * alpha_ * weights_.cwiseProduct(p.segment(offset_, size_) - prior_).squaredNorm();
}

void Tikhonov::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const { (void)x, (void)p, (void)gx; }

// dJ/dq_i = alpha w_i^2 (q_i - q0_i).
void Tikhonov::add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const {
  (void)x;
  check_parameters(p);
  gp.segment(offset_, size_) += alpha_ * weights_.cwiseAbs2().cwiseProduct(p.segment(offset_, size_) - prior_);
}

// J_pp = alpha W^2 on the block; J_xx = J_xp = 0.
void Tikhonov::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                                 Vector& out_p) const {
  (void)x, (void)dx, (void)out_x;
  check_parameters(p);
  out_p.segment(offset_, size_) += alpha_ * weights_.cwiseAbs2().cwiseProduct(dp.segment(offset_, size_));
}

void Tikhonov::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const {
  check_parameters(p);
  const double s = std::sqrt(alpha_);
  r = s * weights_.cwiseProduct(p.segment(offset_, size_) - prior_);
  if (dr_dx) {
    dr_dx->resize(size_, x.size());
    dr_dx->setZero();
  }
  if (dr_dp) {
    Triplets triplets;
    triplets.reserve(static_cast<std::size_t>(size_));
    for (int i = 0; i < size_; ++i) triplets.emplace_back(i, offset_ + i, s * weights_[i]);
    dr_dp->resize(size_, p.size());
    dr_dp->setFromTriplets(triplets.begin(), triplets.end());
  }
}

}  // namespace tailor
