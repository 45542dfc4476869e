#include <cmath>
#include <stdexcept>

#include "forward/dynamics/time_dependent.hpp"

namespace tailor {

TimeVaryingLoadTerm::TimeVaryingLoadTerm(Vector nodal_forces, std::function<double(double)> magnitude,
                                         Vector reference, std::string label)
    : forces_(std::move(nodal_forces)),
      reference_(std::move(reference)),
      magnitude_(std::move(magnitude)),
      label_(std::move(label)) {
  if (reference_.size() != 0 && reference_.size() != forces_.size())
    throw std::invalid_argument("TimeVaryingLoadTerm '" + label_ +
                                "': the reference state has the wrong size");
  if (!magnitude_) throw std::invalid_argument("TimeVaryingLoadTerm '" + label_ + "': no magnitude function");
  set_time(0.0);
}

void TimeVaryingLoadTerm::set_time(double time) {
  magnitude_now_ = magnitude_(time);
  if (!std::isfinite(magnitude_now_))
    throw std::invalid_argument("TimeVaryingLoadTerm '" + label_ +
                                "': magnitude is not finite at t = " + std::to_string(time));
}

void TimeVaryingLoadTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (x.size() != forces_.size())
    throw std::invalid_argument("TimeVaryingLoadTerm '" + label_ +
                                "': force vector size does not match the state");
  if (request.value)
    *request.value -= magnitude_now_ * (reference_.size() ? forces_.dot(x - reference_) : forces_.dot(x));
  if (request.gradient) *request.gradient -= magnitude_now_ * forces_;
}

}  // namespace tailor
