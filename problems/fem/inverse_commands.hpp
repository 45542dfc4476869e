#pragma once
// The work behind `tailor gradcheck` and `tailor run`, callable from C++ (the executable only
// parses arguments and maps outcomes to exit codes). Both need a scene with an "inverse"
// section and throw SceneError / MeshError for bad input, std::runtime_error when an output
// cannot be written; a failed check or optimization is not an exception.
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "problems/fem/inverse_report.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

struct GradcheckSettings {
  std::optional<unsigned> seed;  // overrides inverse.gradcheck.seed
  bool hessian = false;          // also check Hessian-vector products
};

// Taylor test of the scene's reduced functional at the initial design z0 (and of its
// Hessian-vector products when asked); prints the tables to `log` when set and writes
// out_dir/gradcheck.json (creating out_dir).
GradcheckRun gradcheck_scene(const Scene& scene, const std::string& out_dir,
                             const GradcheckSettings& settings, std::ostream* log = nullptr);
// The same for a problem built already (build_inverse_problem with extensions). Tightens the
// problem's functional's Newton tolerances to the round-off floor (they stay so).
GradcheckRun gradcheck_problem(InverseProblem& problem, const std::string& out_dir,
                               const GradcheckSettings& settings, std::ostream* log = nullptr);

struct RunSettings {
  std::optional<int> checkpoint_every;  // overrides inverse.optimizer.checkpoint_every (0: none)
  // A checkpoint to continue from: a folder holding checkpoint.json, or the file.
  std::optional<std::string> resume;
};

// Minimizes the scene's objective over its design from z0 with the scene's back-end; writes
// out_dir/report.json and out_dir/result.vtu at the best design found, also when the
// optimizer stops early (iteration or time limit, Ctrl-C, failure), and out_dir/checkpoint.json
// every checkpoint_every iterations and at the end (problems/optimizer_checkpoint.hpp). With
// settings.resume it continues from that checkpoint instead of z0; a checkpoint of another
// scene, design size or back-end is a SceneError. One progress line per iteration goes to
// `progress`, a summary to `log`, each when set.
InverseRun run_inverse_scene(const Scene& scene, const std::string& out_dir, std::ostream* log = nullptr,
                             std::ostream* progress = nullptr, const RunSettings& settings = {});
// The same for a problem built already, with constraints c(z) <= 0 or = 0 on the design (for
// the back-ends that take them: ipopt, nlopt_slsqp, nlopt_mma inequalities); the run owns the
// problem. The report, result.vtu and plots are those of run_inverse_scene.
InverseRun run_inverse_problem(std::unique_ptr<InverseProblem> problem, const std::string& out_dir,
                               std::ostream* log = nullptr, std::ostream* progress = nullptr,
                               const RunSettings& settings = {},
                               const std::vector<Constraint>& constraints = {});

}  // namespace tailor
