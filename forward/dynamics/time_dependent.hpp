#pragma once
// Terms whose potential depends on time (loads that follow a function of time). The time
// integrator sets the time of the step's end, t_{n+1}, before it solves the step.
#include <functional>

#include "forward/core/energy_term.hpp"

namespace tailor {

class TimeDependent {
 public:
  virtual ~TimeDependent() = default;
  virtual void set_time(double time) = 0;
};

// A dead load whose magnitude follows a function of time: E(x, t) = -s(t) f . (x - X), f nodal
// forces (interleaved like x), s dimensionless, X a reference state (default 0; pass the rest
// positions to keep the potential small near equilibrium, which Newton's line search needs).
class TimeVaryingLoadTerm final : public EnergyTerm, public TimeDependent {
 public:
  TimeVaryingLoadTerm(Vector nodal_forces, std::function<double(double)> magnitude,
                      Vector reference = Vector(), std::string label = "time_varying_load");
  std::string name() const override { return label_; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  bool hessian_is_constant() const override { return true; }  // linear in x
  void set_time(double time) override;
  double magnitude() const { return magnitude_now_; }

 private:
  Vector forces_, reference_;
  std::function<double(double)> magnitude_;
  std::string label_;
  double magnitude_now_;
};

}  // namespace tailor
