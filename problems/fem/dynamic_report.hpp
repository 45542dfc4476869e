#pragma once
// Outputs of `tailor simulate` on a dynamic scene: DIR/frames/frame_NNNNN.vtu every
// `output_every` steps (and the last), DIR/result.pvd (a ParaView time series of the frames)
// and DIR/report.json with per-step energies, Newton iterations and timings (docs/dynamics.md).
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "forward/dynamics/time_integrator.hpp"
#include "problems/fem/dynamic_scene.hpp"

namespace tailor {

struct DynamicStepRecord {
  int step = 0;
  double time = 0.0, kinetic = 0.0, potential = 0.0;
  double seconds = 0.0;   // of this step's solve
  double residual = 0.0;  // the solver's final residual (0 for the initial state)
  int newton_iterations = 0;  // or descent's iterations with dynamics.solver.method "descent"
};

// Wall-clock seconds of the parts of a dynamic run (the steps' own sum is in the report).
struct DynamicTimings {
  double total = 0.0;   // up to (not including) writing report.json
  double setup = 0.0;   // scene, model, initial state
  double output = 0.0;  // writing the frames
};

// What a run with dynamics.reduction used (report.json "reduction").
struct ReducedRunSummary {
  std::string basis, energy;  // as in dynamics.reduction; energy "polynomial" or "projected"
  std::string rotations = "none", rotation_blend;  // dynamics.reduction.rotations and its blend
  int r = 0;                  // reduced coordinates
  int domains = 0;            // 0 for the global basis
  int groups = 0, largest_group = 0;  // the polynomial's element groups and their most columns
  double basis_seconds = 0.0, energy_seconds = 0.0;  // precomputation: the basis, the reduced energy
};

struct DynamicRun {
  bool completed = false;  // every step converged
  std::string message;
  int steps_done = 0;
  std::vector<DynamicStepRecord> records;              // the initial state, then one per step done
  std::vector<std::pair<double, std::string>> frames;  // (time, file relative to DIR)
  DynamicTimings timings;
  std::string report_path, series_path;
  LinearSolverPtr linear_solver;  // the steps' (empty: CHOLMOD)
  std::vector<std::string> warnings;  // problems/fem/physics_warnings.hpp
  std::optional<ReducedRunSummary> reduction;  // set by a reduced run
};

// Writes frames_dir/frame_NNNNN.vtu of state s (point data displacement from `rest` and
// velocity; cell data youngs_modulus) and returns its name relative to DIR ("frames/...").
// Throws std::runtime_error when the file cannot be written.
std::string write_dynamic_frame(const std::filesystem::path& frames_dir, const StaticSetup& setup,
                                const Vector& rest, const DynamicState& s);

// result.pvd listing run.frames; report.json. Both throw std::runtime_error when the file
// cannot be written.
void write_dynamic_series(const std::string& path, const DynamicRun& run);
void write_dynamic_report_json(const std::string& path, const Scene& scene, const DynamicRun& run);

}  // namespace tailor
