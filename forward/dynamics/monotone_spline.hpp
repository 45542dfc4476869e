#pragma once
// A monotone-preserving piecewise cubic Hermite interpolant of control values y_k at
// increasing knots t_k (Fritsch & Carlson, SIAM J. Numer. Anal. 17, 1980), with interior
// slopes from Fritsch & Butland's weighted harmonic mean of the neighbouring secants
//   m_k = (w1 + w2) / (w1 / d_{k-1} + w2 / d_k),  w1 = 2 h_k + h_{k-1}, w2 = h_k + 2 h_{k-1},
// (m_k = 0 where the secants d differ in sign or vanish), end slopes equal to the end
// secants, and constant extension outside [t_0, t_N]. The curve never leaves the range of
// the control values, so non-negative controls give a non-negative curve. It is C1 in t and
// differentiable in y wherever neighbouring secants are nonzero (a flat or turning segment
// makes it only Lipschitz in y there). One knot: the constant y_0.
#include "forward/core/types.hpp"

namespace tailor {

class MonotoneCubic {
 public:
  // Throws std::invalid_argument unless knots are finite and strictly increasing (>= 1).
  explicit MonotoneCubic(Vector knots);

  int size() const { return static_cast<int>(knots_.size()); }
  const Vector& knots() const { return knots_; }

  // s(t) for control values y (size()); optionally ds/dt and ds/dy (size()).
  double evaluate(const Vector& y, double t, double* slope = nullptr,
                  Vector* control_gradient = nullptr) const;

 private:
  Vector knots_;
};

}  // namespace tailor
