#pragma once
// Implicit time steps whose incremental potential is minimised by the descent solver
// (forward/dynamics/descent_solver.hpp) instead of Newton: the same schemes, terms and state
// update as TimeIntegrator::step (forward/dynamics/time_integrator.hpp), which configures each
// step here. The warm start is the previous step's state; the stopping measure is Newton's
// (relative to the largest initial step residual so far, with the round-off floor of the
// integrator's state as an absolute floor). A step stopped by the iteration budget is taken,
// with its reached residual in the result: descent stopped early is not Newton's answer, and
// descent_bench measures how far it is.
#include "forward/dynamics/descent_solver.hpp"
#include "forward/dynamics/time_integrator.hpp"

namespace tailor {

class DescentTimeStepper {
 public:
  // The integrator supplies the model, the scheme and the per-step configuration; it must
  // outlive the stepper. Throws what DescentSolver's constructor throws.
  DescentTimeStepper(TimeIntegrator& integrator, DescentOptions options);

  // Advances one step. When the result is not usable (a non-finite energy) the state is left
  // unchanged.
  DescentResult step(DynamicState& state, const Vector& p);

  DescentSolver& solver() { return solver_; }

 private:
  TimeIntegrator& integrator_;
  DescentSolver solver_;
};

}  // namespace tailor
