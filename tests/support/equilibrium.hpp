#pragma once
// The static equilibrium of a Model from its rest state, for tests: Newton to a relative
// tolerance of 1e-12, checked to converge (a failure is reported, the last iterate returned).
#include <gtest/gtest.h>

#include "forward/core/model.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::testing {

inline Vector solve_equilibrium(const Model& model, const Vector& p, const Vector& rest) {
  NewtonOptions options;
  options.relative_tolerance = 1e-12;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(rest);
  const NewtonResult r = solver.solve(p, y);
  EXPECT_TRUE(r.converged()) << r.report();
  return model.elimination().expand(y);
}

}  // namespace tailor::testing
