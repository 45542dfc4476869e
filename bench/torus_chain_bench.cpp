// A hanging chain of interlocked tori (forward/tori, docs/tori.md), implicit torus contact
// against the same tori as triangle meshes with mesh IPC (forward/rigid/rigid_contact_term.hpp).
//  1. Dynamics: --links tori (default 100; R = 1, r = 0.2, 1000 kg/m^3), the first fixed,
//     released --tilt rad from the vertical, --steps implicit Euler steps of --time-step, for
//     each model: seconds, Newton iterations, CCD share (max_step's time over the step's),
//     active contact pairs and smallest distance per step (medians reported), and mesh
//     edge-face crossings after every step (must be 0).
//  2. Speed against error: the static equilibrium of --static-links tori (relaxation with 10 s
//     steps) with the implicit model and with mesh IPC at each --segments resolution: time per
//     relaxation step and the largest difference of the link centres from the implicit ones.
// Writes JSON (--out, default bench_torus_chain.json) and prints tables.
//
// usage: torus_chain_bench [--links 100] [--steps 20] [--time-step 0.01] [--tilt 0.3]
//                          [--mesh-segments 24] [--static-links 10] [--segments 12,16,24,32]
//                          [--pair-band 2] [--max-iterations 100] [--out FILE]
// Contact pairs: torus pairs within d_hat (implicit), primitive point-triangle and edge-edge
// pairs within d_hat (mesh).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/statistics.hpp"
#include "forward/tori/chain_simulation.hpp"

namespace tailor::bench::torus_chain_bench {

using namespace tailor;
using namespace tailor::tori;

namespace {

double median_of(const std::vector<double>& v) { return v.empty() ? 0.0 : median(v); }

struct DynamicSummary {
  int completed = 0, intersections = 0;
  double median_seconds = 0, median_newton = 0, ccd_share = 0, median_pairs = 0, total_seconds = 0;
  double min_distance = std::numeric_limits<double>::infinity();
  std::string failure;
};

DynamicSummary run_dynamic(const ChainSpec& chain, ContactModel model, double h, int steps, int band,
                           int max_iterations, bench::Json& out) {
  ChainSimulationOptions o;
  o.newton.max_iterations = max_iterations;
  o.model = model;
  o.time_step = h;
  o.pair_band = band;
  ChainSimulation sim(chain, o);
  std::vector<double> seconds, newton, pairs;
  double ccd = 0.0;
  DynamicSummary s;
  bench::Json per_step = bench::Json::array();
  for (int n = 0; n < steps; ++n) {
    const ChainStepRecord r = sim.step();
    per_step.push_back({{"step", n + 1},
                        {"converged", r.converged},
                        {"seconds", r.seconds},
                        {"ccd_seconds", r.ccd_seconds},
                        {"newton_iterations", r.newton_iterations},
                        {"active_pairs", r.active_pairs},
                        {"min_distance", r.min_distance},
                        {"intersections", r.intersections}});
    if (!r.converged) {
      s.failure = sim.last_message();
      break;
    }
    ++s.completed;
    seconds.push_back(r.seconds);
    newton.push_back(r.newton_iterations);
    pairs.push_back(r.active_pairs);
    ccd += r.ccd_seconds;
    s.total_seconds += r.seconds;
    s.intersections += std::max(0, r.intersections);
    s.min_distance = std::min(s.min_distance, r.min_distance);
  }
  s.median_seconds = median_of(seconds);
  s.median_newton = median_of(newton);
  s.median_pairs = median_of(pairs);
  s.ccd_share = s.total_seconds > 0 ? ccd / s.total_seconds : 0.0;
  out = {{"model", model == ContactModel::implicit ? "implicit" : "mesh"},
         {"activation_distance", sim.activation_distance()},
         {"stiffness", sim.stiffness()},
         {"steps_completed", s.completed},
         {"failure", s.failure},
         {"median_seconds_per_step", s.median_seconds},
         {"median_newton_per_step", s.median_newton},
         {"ccd_share", s.ccd_share},
         {"median_active_pairs", s.median_pairs},
         {"min_distance", s.min_distance},
         {"intersections", s.intersections},
         {"per_step", per_step}};
  return s;
}

struct StaticResult {
  bool rested = false;
  Vector state;
  double median_seconds = 0;
  int steps = 0;
};

StaticResult run_static(const ChainSpec& chain, ContactModel model, int max_iterations) {
  ChainSimulationOptions o;
  o.newton.max_iterations = max_iterations;
  o.model = model;
  o.time_step = 10.0;
  o.check_intersections = true;
  ChainSimulation sim(chain, o);
  std::vector<ChainStepRecord> records;
  StaticResult r;
  r.rested = sim.relax(1e-7, 400, &records);
  std::vector<double> seconds;
  for (const ChainStepRecord& k : records) {
    seconds.push_back(k.seconds);
    if (k.intersections > 0) r.rested = false;
  }
  r.median_seconds = median_of(seconds);
  r.steps = static_cast<int>(records.size());
  r.state = sim.state();
  return r;
}

}  // namespace

int run(int argc, char** argv) {
  int links = 100, steps = 20, mesh_segments = 24, static_links = 10, band = 2, max_iterations = 100;
  double h = 0.01, tilt = 0.3;
  std::vector<int> segments = {12, 16, 24, 32};
  std::string out = "bench_torus_chain.json";
  bench::Cli cli("torus_chain_bench", "A hanging chain of tori: implicit torus contact against mesh IPC.");
  cli.integer("--links", links, "tori in the dynamic chain", 2);
  cli.steps(steps);
  cli.time_step(h);
  cli.number("--tilt", tilt, "release angle from the vertical [rad]", 0.0, true);
  cli.integer("--mesh-segments", mesh_segments,
              "major segments of the dynamic run's meshes (minor: a quarter, >= 6)", 8);
  cli.integer("--static-links", static_links, "tori in the static comparison", 2);
  cli.integers("--segments", segments, "major segments of the static comparison's meshes", 8);
  cli.integer("--max-iterations", max_iterations, "Newton iteration cap per step", 1);
  cli.integer("--pair-band", band, "implicit model: candidate pairs |i - j| <= band (0: all)", 0);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;

  bench::Json json = bench::report("torus_chain");
  ChainSpec chain;
  chain.count = links;
  chain.shape = {1.0, 0.2};
  chain.tilt = tilt;
  chain.major_segments = mesh_segments;
  chain.minor_segments = std::max(6, mesh_segments / 4);
  json["dynamic"] = {{"links", links},
                     {"steps", steps},
                     {"time_step", h},
                     {"tilt", tilt},
                     {"mesh_segments", {chain.major_segments, chain.minor_segments}},
                     {"pair_band", band},
                     {"max_iterations", max_iterations}};
  std::printf("dynamic chain: %d links, %d steps of %g s, released %g rad from the vertical\n", links, steps,
              h, tilt);
  std::printf("%-9s %9s %12s %12s %9s %11s %12s %8s\n", "model", "steps", "s/step", "Newton/step", "CCD %",
              "pairs", "min dist", "crossing");
  bench::Json models = bench::Json::array();
  for (ContactModel model : {ContactModel::implicit, ContactModel::mesh}) {
    bench::Json m;
    const DynamicSummary s = run_dynamic(chain, model, h, steps, band, max_iterations, m);
    models.push_back(m);
    std::printf("%-9s %9d %12.4f %12.1f %9.1f %11.0f %12.3e %8d%s\n",
                model == ContactModel::implicit ? "implicit" : "mesh", s.completed, s.median_seconds,
                s.median_newton, 100.0 * s.ccd_share, s.median_pairs, s.min_distance, s.intersections,
                s.failure.empty() ? "" : ("  FAILED: " + s.failure).c_str());
  }
  json["dynamic"]["models"] = models;

  // Speed against error: static equilibria.
  ChainSpec st = chain;
  st.count = static_links;
  st.tilt = 0.0;
  const StaticResult reference = run_static(st, ContactModel::implicit, max_iterations);
  std::printf("\nstatic chain: %d links (implicit: %s in %d steps, %.4f s/step)\n", static_links,
              reference.rested ? "at rest" : "NOT at rest", reference.steps, reference.median_seconds);
  std::printf("%-14s %9s %12s %16s %16s\n", "mesh", "steps", "s/step", "max |dT| [m]", "bottom dz [m]");
  bench::Json comparison = bench::Json::array();
  for (int major : segments) {
    st.major_segments = major;
    st.minor_segments = std::max(6, major / 4);
    const StaticResult mesh = run_static(st, ContactModel::mesh, max_iterations);
    double worst = 0.0;
    for (int b = 0; b < static_links; ++b)
      worst = std::max(worst, (mesh.state.segment<3>(6 * b) - reference.state.segment<3>(6 * b)).norm());
    const double dz = mesh.state[6 * (static_links - 1) + 2] - reference.state[6 * (static_links - 1) + 2];
    std::printf("%4d x %-7d %9d %12.4f %16.3e %16.3e%s\n", st.major_segments, st.minor_segments, mesh.steps,
                mesh.median_seconds, worst, dz, mesh.rested ? "" : "  (a step failed or crossed)");
    comparison.push_back({{"segments", {st.major_segments, st.minor_segments}},
                          {"rested", mesh.rested},
                          {"steps", mesh.steps},
                          {"median_seconds_per_step", mesh.median_seconds},
                          {"max_centre_difference", worst},
                          {"bottom_height_difference", dz}});
  }
  json["static"] = {{"links", static_links},
                    {"implicit",
                     {{"rested", reference.rested},
                      {"steps", reference.steps},
                      {"median_seconds_per_step", reference.median_seconds}}},
                    {"mesh", comparison}};
  return bench::write_report(out, json, "torus_chain_bench") ? 0 : 1;
}

}  // namespace tailor::bench::torus_chain_bench
