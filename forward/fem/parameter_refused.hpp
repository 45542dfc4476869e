#pragma once
// What lame_from_young_poisson (forward/fem/material.hpp) throws for E not finite and > 0, or nu
// outside (-1, 1/2): parameters the model cannot take. adjoint/static_functional.cpp makes it an
// EvaluationError, so that an optimizer's trial design there is a failed evaluation.
#include <stdexcept>

namespace tailor {

class ParameterRefused : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace tailor
