// Constant generalized loads (see rigid_load_term.hpp).
#include "forward/rigid/rigid_load_term.hpp"

#include <stdexcept>
#include <string>

namespace tailor::rigid {

RigidLoadTerm::RigidLoadTerm(Vector loads, Vector reference) : reference_(std::move(reference)) {
  set_loads(std::move(loads));
}

void RigidLoadTerm::set_loads(Vector loads) {
  if (loads.size() != reference_.size())
    throw std::invalid_argument("RigidLoadTerm: " + std::to_string(loads.size()) + " loads for " +
                                std::to_string(reference_.size()) + " DOFs");
  loads_ = std::move(loads);
}

void RigidLoadTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (request.value) *request.value -= loads_.dot(x - reference_);
  if (request.gradient) *request.gradient -= loads_;
}

}  // namespace tailor::rigid
