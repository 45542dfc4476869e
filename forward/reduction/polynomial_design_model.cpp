#include "forward/reduction/polynomial_design_model.hpp"

#include <stdexcept>
#include <string>

#include "forward/reduction/reduced_stvk.hpp"

namespace tailor {
namespace {

// s(q) = [q; (q_a q_b)_{a <= b}] (or q alone without pairs).
Vector lifted(const Vector& q, bool pairs) {
  const int r = static_cast<int>(q.size());
  if (!pairs) return q;
  Vector s(r + r * (r + 1) / 2);
  s.head(r) = q;
  for (int a = 0, k = r; a < r; ++a)
    for (int b = a; b < r; ++b, ++k) s[k] = q[a] * q[b];
  return s;
}

// [v; J_s v]: the derivative of s(q) along v.
Vector lifted_tangent(const Vector& q, const Vector& v, bool pairs) {
  const int r = static_cast<int>(q.size());
  if (!pairs) return v;
  Vector s(r + r * (r + 1) / 2);
  s.head(r) = v;
  for (int a = 0, k = r; a < r; ++a)
    for (int b = a; b < r; ++b, ++k) s[k] = q[a] * v[b] + v[a] * q[b];
  return s;
}

void evaluate_with(const Matrix& g, bool quadratic, const Vector& q, double* energy, Vector* force,
                   Matrix* stiffness) {
  if (quadratic) {
    evaluate_stvk_polynomial(g, q, energy, force, stiffness);
    return;
  }
  const Vector gq = g * q;
  if (energy) *energy = 0.5 * q.dot(gq);
  if (force) *force = gq;
  if (stiffness) *stiffness = g;
}

}  // namespace

PolynomialDesignModel::PolynomialDesignModel(Matrix base, std::vector<Matrix> modes, int r,
                                             const std::string& context)
    : base_(std::move(base)), modes_(std::move(modes)), r_(r) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(context + ": " + what); };
  if (r_ < 1) fail("empty load (r = 0)");
  const int width = static_cast<int>(base_.rows());
  if (width == r_ + r_ * (r_ + 1) / 2)
    quadratic_ = true;
  else if (width != r_)
    fail("the coefficients are " + std::to_string(width) + " wide; expected r = " + std::to_string(r_) +
         " or r + r (r + 1) / 2 = " + std::to_string(r_ + r_ * (r_ + 1) / 2));
  if (base_.cols() != width) fail("the base coefficients are not square");
  if (modes_.empty()) fail("no design coordinate (no material mode)");
  for (const Matrix& g : modes_)
    if (g.rows() != width || g.cols() != width) fail("a mode's coefficients differ in size from the base");
}

Matrix PolynomialDesignModel::coefficients(const Vector& w) const {
  if (w.size() != design_size())
    throw std::invalid_argument("PolynomialDesignModel: w has " + std::to_string(w.size()) +
                                " entries, expected " + std::to_string(design_size()));
  Matrix g = base_;
  for (int j = 0; j < design_size(); ++j) g.noalias() += w[j] * modes_[static_cast<std::size_t>(j)];
  return g;
}

void PolynomialDesignModel::evaluate(const Vector& q, const Vector& w, double* energy, Vector* force,
                                     Matrix* stiffness) const {
  if (q.size() != r_)
    throw std::invalid_argument("PolynomialDesignModel: q has " + std::to_string(q.size()) +
                                " entries, expected " + std::to_string(r_));
  evaluate_with(coefficients(w), quadratic_, q, energy, force, stiffness);
}

ReducedDesignModel::AtDesign PolynomialDesignModel::at_design(const Vector& w) const {
  return [g = coefficients(w), quadratic = quadratic_, r = r_](const Vector& q, double* energy, Vector* force,
                                                               Matrix* stiffness) {
    if (q.size() != r) throw std::invalid_argument("PolynomialDesignModel: q has the wrong size");
    evaluate_with(g, quadratic, q, energy, force, stiffness);
  };
}

Matrix PolynomialDesignModel::force_design_derivative(const Vector& q) const {
  Matrix d(r_, design_size());
  Vector f;
  for (int j = 0; j < design_size(); ++j) {
    evaluate_with(modes_[static_cast<std::size_t>(j)], quadratic_, q, nullptr, &f, nullptr);
    d.col(j) = f;
  }
  return d;
}

Vector PolynomialDesignModel::force_design_derivative_transpose(const Vector& q, const Vector& lambda) const {
  // lambda^T dW_j/dq = d/dt W_j(q + t lambda) = [lambda; J_s lambda]^T G_j s(q).
  const Vector s = lifted(q, quadratic_), ls = lifted_tangent(q, lambda, quadratic_);
  Vector out(design_size());
  for (int j = 0; j < design_size(); ++j) out[j] = ls.dot(modes_[static_cast<std::size_t>(j)] * s);
  return out;
}

}  // namespace tailor
