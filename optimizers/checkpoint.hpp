#pragma once
// The state of a minimize() run from which another minimize() call can continue: what
// OptimizerOptions::on_checkpoint receives and minimize(..., resume) takes. Plain data; writing
// it to a file is the caller's business (tailor run: problems/optimizer_checkpoint.hpp).
//
// What a resumed run takes back, per back-end (everything else restarts at the iterate z):
//  - gradient_descent: everything. Its state is the iterate and the last accepted step length
//    ("step"), so it continues along the same path.
//  - ceres_least_squares: the trust-region radius ("trust_region_radius"); the
//    Levenberg-Marquardt damping's growth factor and the active-set rounds start afresh.
//  - newton_cg: the trust-region radius ("trust_region_radius"); its CG restarts at the iterate
//    anyway (it keeps no memory across iterations).
//  - ceres_lbfgs: nothing. Ceres keeps its L-BFGS memory and line-search state private.
//  - nlopt_lbfgs, nlopt_mma, nlopt_slsqp: nothing. NLopt exposes neither the L-BFGS memory, MMA's
//    asymptotes nor SLSQP's quasi-Newton matrix.
//  - ipopt: nothing. Ipopt 3.11 does not give out its L-BFGS memory, and its barrier parameter
//    and multipliers are not taken back (a warm start needs all of them to help).
// Back-ends that restart their memory take more iterations after a resume than an uninterrupted
// run would, and reach the same minimum to within their tolerances.
#include <map>
#include <string>
#include <vector>

#include "optimizers/optimizer.hpp"

namespace tailor {

struct OptimizerCheckpoint {
  OptimizerBackend backend = OptimizerBackend::nlopt_lbfgs;
  int iteration = 0;  // history.back().iteration
  Vector z;           // the iterate of that row
  double objective = 0.0;
  // The best point so far (it may differ from z with constraints, or for back-ends whose rows
  // are not improving points).
  Vector best_z;
  double best_objective = 0.0;
  double best_violation = 0.0;
  std::vector<OptimizerIteration> history;
  int evaluations = 0;
  int failed_evaluations = 0;
  double seconds = 0.0;         // of the run up to the checkpoint
  FunctionalCounters counters;  // the functional's work up to the checkpoint
  // The back-end's own state that a resumed run takes back (see above), by name.
  std::map<std::string, double> backend_state;
};

}  // namespace tailor
