#pragma once
// Least-squares fit of a compliance from sampled macro (stress, strain) pairs (docs/methods.md
// section 12):  S = argmin over symmetric S of  sum_i ||S sigma_i - eps_i||^2 / ||eps_i||^2,
// Voigt vectors in the convention of linear_homogenization.hpp (engineering shear strains).
// The problem is linear in the m(m+1)/2 entries of S, so it is solved directly (QR) rather
// than iteratively.
#include <vector>

#include "forward/core/types.hpp"
#include "forward/homogenization/nonlinear_homogenization.hpp"

namespace tailor {

struct StressStrainSample {
  Vector stress;  // Voigt, plain
  Vector strain;  // Voigt, engineering shear
};

// Throws std::invalid_argument for inconsistent sizes, a zero strain, or samples that do not
// determine S (rank deficient: fewer than about m(m+1)/(2m) independent load directions).
Matrix fit_compliance(const std::vector<StressStrainSample>& samples);

// The sample of a nonlinear response: strain (F + F^T)/2 - I and the symmetric part of the
// macro first Piola-Kirchhoff stress (the seed's measures; exact to first order in the strain).
StressStrainSample macro_sample(const MacroResponse& response);

}  // namespace tailor
