#pragma once
// EmbeddedTerm: an EnergyTerm of a sub-model (e.g. an FEM body's elasticity over its own vertex
// DOFs 0 .. n-1 and parameters 0 .. m-1) placed into a larger state and parameter vector:
//   E(x, p) = E_inner(x[state_offset .. state_offset + n), p[parameter_offset .. + m)).
// Derivatives are the inner term's, with rows and columns shifted; the inner term must outlive
// this one. Used to put FEM bodies next to rigid bodies in one contact model.
#include "forward/core/energy_term.hpp"

namespace tailor {

class EmbeddedTerm final : public EnergyTerm {
 public:
  EmbeddedTerm(const EnergyTerm& inner, int state_offset, int state_size, int parameter_offset,
               int parameter_size)
      : inner_(inner), x0_(state_offset), nx_(state_size), p0_(parameter_offset), np_(parameter_size) {}

  std::string name() const override { return inner_.name(); }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    Vector gradient;
    EnergyRequest inner = request;
    if (request.gradient) {
      gradient = Vector::Zero(nx_);
      inner.gradient = &gradient;
    }
    inner_.evaluate(x.segment(x0_, nx_), sub_p(p), inner);
    if (request.gradient) request.gradient->segment(x0_, nx_) += gradient;
  }
  void hessian_pattern(HessianPattern& pattern) const override {
    HessianPattern inner;
    inner_.hessian_pattern(inner);
    for (const auto& [row, col] : inner) pattern.push_back({row + x0_, col + x0_});
  }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override {
    Vector g = Vector::Zero(np_);
    inner_.add_param_gradient(x.segment(x0_, nx_), sub_p(p), g);
    if (np_ > 0) gradient_p.segment(p0_, np_) += g;
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override {
    Triplets inner;
    inner_.add_mixed(x.segment(x0_, nx_), sub_p(p), inner);
    for (const auto& t : inner) mixed.emplace_back(t.row() + x0_, t.col() + p0_, t.value());
  }
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override {
    Vector g = Vector::Zero(np_);
    inner_.add_mixed_transpose_times(x.segment(x0_, nx_), sub_p(p), w.segment(x0_, nx_), g);
    if (np_ > 0) gradient_p.segment(p0_, np_) += g;
  }
  void add_low_rank_hessian(const Vector& x, const Vector& p, LowRankHessian& update,
                            HessianMode mode) const override {
    LowRankHessian inner;
    inner_.add_low_rank_hessian(x.segment(x0_, nx_), sub_p(p), inner, mode);
    if (inner.empty()) return;
    Matrix factors = Matrix::Zero(x.size(), inner.factors.cols());
    factors.middleRows(x0_, nx_) = inner.factors;
    update.append(factors, inner.core);
  }
  bool hessian_is_constant() const override { return inner_.hessian_is_constant(); }
  std::uint64_t hessian_revision() const override { return inner_.hessian_revision(); }
  double max_step(const Vector& x, const Vector& dx) const override {
    return inner_.max_step(x.segment(x0_, nx_), dx.segment(x0_, nx_));
  }

 private:
  Vector sub_p(const Vector& p) const { return np_ > 0 ? Vector(p.segment(p0_, np_)) : Vector(); }
  const EnergyTerm& inner_;
  int x0_, nx_, p0_, np_;
};

}  // namespace tailor
