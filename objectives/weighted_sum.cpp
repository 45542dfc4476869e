#include "objectives/weighted_sum.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace tailor {
namespace {

// Appends the nonzeros of `block` to `triplets`, scaled and shifted down by `row_offset`.
void append_rows(const SparseMatrix& block, double scale, int row_offset, Triplets& triplets) {
  for (int col = 0; col < block.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(block, col); it; ++it)
      triplets.emplace_back(row_offset + static_cast<int>(it.row()), static_cast<int>(it.col()), scale * it.value());
}

}  // namespace

WeightedSum::WeightedSum(std::vector<ObjectivePtr> parts, std::vector<double> coefficients)
    : parts_(std::move(parts)), coefficients_(std::move(coefficients)) {
  if (parts_.empty()) throw std::invalid_argument("WeightedSum: no parts");
  if (coefficients_.size() != parts_.size())
    throw std::invalid_argument("WeightedSum: " + std::to_string(parts_.size()) + " parts but " +
                                std::to_string(coefficients_.size()) + " coefficients");
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    if (!parts_[k]) throw std::invalid_argument("WeightedSum: part " + std::to_string(k) + " is null");
    if (!std::isfinite(coefficients_[k]))
      throw std::invalid_argument("WeightedSum: coefficient " + std::to_string(k) + " is not finite");
  }
}

std::string WeightedSum::name() const {
  std::ostringstream s;
  s << "weighted_sum(";
  for (std::size_t k = 0; k < parts_.size(); ++k) s << (k ? " + " : "") << coefficients_[k] << "*" << parts_[k]->name();
  s << ")";
  return s.str();
}

double WeightedSum::value(const Vector& x, const Vector& p) const {
  double J = 0.0;
  for (std::size_t k = 0; k < parts_.size(); ++k) J += coefficients_[k] * parts_[k]->value(x, p);
  return J;
}

// Each part adds into a zeroed buffer so that its contribution can be scaled by c_k.
void WeightedSum::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const {
  Vector part(gx.size());
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    part.setZero();
    parts_[k]->add_gradient_x(x, p, part);
    gx += coefficients_[k] * part;
  }
}

void WeightedSum::add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const {
  Vector part(gp.size());
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    part.setZero();
    parts_[k]->add_gradient_p(x, p, part);
    gp += coefficients_[k] * part;
  }
}

bool WeightedSum::has_second_derivatives() const {
  return std::all_of(parts_.begin(), parts_.end(), [](const ObjectivePtr& J) { return J->has_second_derivatives(); });
}

void WeightedSum::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp,
                                    Vector& out_x, Vector& out_p) const {
  if (!has_second_derivatives())
    throw std::logic_error("WeightedSum: a part has no second derivatives (" + name() + ")");
  Vector part_x(out_x.size()), part_p(out_p.size());
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    part_x.setZero();
    part_p.setZero();
    parts_[k]->add_hessian_times(x, p, dx, dp, part_x, part_p);
    out_x += coefficients_[k] * part_x;
    out_p += coefficients_[k] * part_p;
  }
}

bool WeightedSum::is_least_squares() const {
  for (std::size_t k = 0; k < parts_.size(); ++k)
    if (!parts_[k]->is_least_squares() || coefficients_[k] < 0) return false;
  return true;
}

int WeightedSum::num_residuals() const {
  if (!is_least_squares()) return 0;
  int m = 0;
  for (const auto& J : parts_) m += J->num_residuals();
  return m;
}

void WeightedSum::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                            SparseMatrix* dr_dp) const {
  if (!is_least_squares())
    throw std::logic_error("WeightedSum: not a least-squares objective (a part is not, or has c_k < 0): " + name());
  const int m = num_residuals();
  r.resize(m);
  Triplets tx, tp;
  SparseMatrix jx, jp;
  Vector rk;
  int offset = 0;
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const double s = std::sqrt(coefficients_[k]);
    const int mk = parts_[k]->num_residuals();
    parts_[k]->residuals(x, p, rk, dr_dx ? &jx : nullptr, dr_dp ? &jp : nullptr);
    r.segment(offset, mk) = s * rk;
    if (dr_dx) append_rows(jx, s, offset, tx);
    if (dr_dp) append_rows(jp, s, offset, tp);
    offset += mk;
  }
  if (dr_dx) {
    dr_dx->resize(m, x.size());
    dr_dx->setFromTriplets(tx.begin(), tx.end());
  }
  if (dr_dp) {
    dr_dp->resize(m, p.size());
    dr_dp->setFromTriplets(tp.begin(), tp.end());
  }
}

}  // namespace tailor
