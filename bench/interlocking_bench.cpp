// Strain-space boundaries of periodic interlocking cells (forward/interlocking) and the design of
// their limits. Cells: 1 element (a flat ring lattice, spacing 2.5: it locks where neighbours
// touch and is free in stretch), 4 elements (the threefold mail: a node ring and three links) and
// 16 elements (its 2 x 2 supercell). For each: the boundary in --directions uniaxial directions
// (time per sample: median; time per boundary), with the limits, locked and refined counts and
// the smallest certified clearance; then the first --reference-directions of the sweep again
// without the broad phase (every pair through the contact term): the median CPU time per sample
// before the broad phase, and whether the limits are equal. Then the square ring net's limit design (x links' R and r
// against 1.5x the stretch along x): seconds per design iteration (MMA) and per functional
// evaluation with its gradient. Writes JSON (--out, default bench_interlocking.json) and prints
// tables.
//
// Mesh bodies (--mesh-segments M1,M2,...: rings meshed M x M/2, forward/interlocking/
// periodic_mesh_*): the chain's uniaxial limit per resolution against the closed form 2 (R - r)
// - d_hat / 2 over s0, minus 1, with the chordal bound 2 delta / s0 (the convergence table); and
// the square ring net's first --mesh-directions principal directions, meshed and as implicit tori:
// CPU seconds per boundary sample (median) and the limits' largest difference. --mesh-only skips
// the tori cells and the design.
//
// --bending-convergence: instead, the square ring net's single-curvature limit along x, periodic
// (curved_periodicity.hpp) against finite paraboloid disc patches of growing radius (rim width
// 1.6, --patch-radii in tenths): radius, elements, limit, difference to the periodic limit, CPU s.
//
// usage: interlocking_bench [--directions 32] [--reference-directions 4] [--cells 1,4,16]
//                           [--mesh-segments 12,16,24] [--mesh-directions 4] [--mesh-only] [--out FILE]
//        interlocking_bench --bending-convergence [--patch-radii 31,46,61] [--out FILE]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <limits>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/statistics.hpp"
#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/interpenetration_check.hpp"
#include "forward/interlocking/periodic_mesh_contact.hpp"
#include "forward/interlocking/single_curvature_limit.hpp"
#include "problems/interlocking/limit_design.hpp"

namespace tailor::bench::interlocking_bench {

using namespace tailor::interlocking;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

const tori::TorusShape kRing{1.0, 0.2};

RigidCellSpec cell_of(int elements) {
  if (elements == 1) {
    RigidCellSpec c;
    c.elements = {flat_ring(kRing, Eigen::Vector3d::Zero())};
    c.lattice << 2.5, 0.0, 0.0, 2.5;
    return c;
  }
  const RigidCellSpec mail = threefold_cell(kRing, kRing, 1.5);
  return elements == 4 ? mail : supercell(mail, 2, 2);
}

// The all-pairs reference (no broad phase) on the first `directions` of the same sweep: its
// median CPU seconds per sample and whether every limit equals the broad phase's.
Json all_pairs_reference(int elements, int directions, int sweep, const std::vector<double>& limits,
                         const std::vector<double>& broad_cpu_seconds) {
  RigidCellSpec spec = cell_of(elements);
  spec.broad_phase = false;
  const PeriodicRigidCell cell(spec);
  LimitOptions options;
  options.max_strain = 0.5;
  const Vector y_rest = rest_equilibrium(cell);
  std::vector<double> cpu_seconds;
  bool equal = true;
  for (int k = 0; k < std::min(directions, sweep); ++k) {
    const std::clock_t cs = std::clock();
    const LimitPoint p = find_limit(cell, uniaxial_path(M_PI * k / sweep), y_rest, options);
    cpu_seconds.push_back(static_cast<double>(std::clock() - cs) / CLOCKS_PER_SEC);
    equal = equal && p.strain == limits[static_cast<std::size_t>(k)];
  }
  const std::vector<double> broad(broad_cpu_seconds.begin(),
                                  broad_cpu_seconds.begin() + static_cast<std::ptrdiff_t>(cpu_seconds.size()));
  return {{"directions", static_cast<int>(cpu_seconds.size())},
          {"median_cpu_seconds_per_sample", cpu_seconds.empty() ? 0.0 : median(cpu_seconds)},
          {"broad_phase_median_cpu_seconds_same_samples", broad.empty() ? 0.0 : median(broad)},
          {"limits_equal_to_broad_phase", equal}};
}

Json boundary(int elements, int directions, int reference_directions) {
  const PeriodicRigidCell cell(cell_of(elements));
  LimitOptions options;
  options.max_strain = 0.5;
  // Timed: the rest equilibrium and the limit searches (wall and process CPU time; the clearance
  // check afterwards is not part of a boundary's cost).
  const auto t0 = Clock::now();
  const std::clock_t c0 = std::clock();
  const Vector y_rest = rest_equilibrium(cell);
  double total = seconds_since(t0), cpu_total = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  std::vector<double> seconds, cpu_seconds, limits;
  int locked = 0, refined = 0, solves = 0;
  double clearance = std::numeric_limits<double>::infinity();
  for (int k = 0; k < directions; ++k) {
    const auto ts = Clock::now();
    const std::clock_t cs = std::clock();
    const LimitPoint p = find_limit(cell, uniaxial_path(M_PI * k / directions), y_rest, options);
    seconds.push_back(seconds_since(ts));
    cpu_seconds.push_back(static_cast<double>(std::clock() - cs) / CLOCKS_PER_SEC);
    total += seconds.back();
    cpu_total += cpu_seconds.back();
    limits.push_back(p.strain);
    locked += p.locked;
    refined += p.refined;
    solves += p.solves;
    clearance = std::min(clearance, check_clearance(cell, cell.full_state(p.y, p.deformation), 1 << 14).min_lower);
  }
  const double med = median(seconds), cpu_med = median(cpu_seconds);
  const Json reference = all_pairs_reference(elements, reference_directions, directions, limits, cpu_seconds);
  std::printf("%8d %6d %10d %12.4f %12.4f %12.2f %12.2f %8d %8d %10.1f %12.3e %10.5f %10.5f %14.4f %14.4f %6s\n", elements,
              cell.num_free(), directions, med, cpu_med, total, cpu_total, locked, refined,
              static_cast<double>(solves) / directions, clearance, *std::min_element(limits.begin(), limits.end()),
              *std::max_element(limits.begin(), limits.end()),
              reference["broad_phase_median_cpu_seconds_same_samples"].get<double>(),
              reference["median_cpu_seconds_per_sample"].get<double>(),
              reference["limits_equal_to_broad_phase"].get<bool>() ? "yes" : "NO");
  return {{"elements", elements},
          {"free_dofs", cell.num_free()},
          {"bodies", cell.num_bodies()},
          {"directions", directions},
          {"median_seconds_per_sample", med},
          {"seconds_per_boundary", total},
          {"median_cpu_seconds_per_sample", cpu_med},
          {"cpu_seconds_per_boundary", cpu_total},
          {"locked", locked},
          {"refined", refined},
          {"solves_per_sample", static_cast<double>(solves) / directions},
          {"min_certified_clearance", clearance},
          {"limits", array(limits)},
          {"cpu_seconds_per_sample", array(cpu_seconds)},
          {"all_pairs_reference", reference}};
}

Json design() {
  const RigidCellSpec start = square_ring_cell(kRing, kRing, kRing, 1.5);
  const std::vector<DesignVariable> variables = {{1, true, 0.9, 1.2}, {1, false, 0.15, 0.25}};
  const double base = (1.6 - 0.0005) / 1.5 - 1.0;
  const std::vector<LimitTarget> targets = {{uniaxial_path(0.0), 1.5 * base}, {uniaxial_path(0.5 * M_PI), base}};
  LimitDesignFunctional functional(start, variables, targets, {});
  // One evaluation with its gradient from a warm start (the continuation of the last limits).
  const Vector z0 = functional.initial_design();
  Vector g;
  functional.value_and_gradient(z0, g);
  std::vector<double> eval;
  for (int k = 0; k < 5; ++k) {
    const auto t = Clock::now();
    functional.value_and_gradient(z0 + Vector::Constant(z0.size(), 1e-4 * (k + 1)), g);
    eval.push_back(seconds_since(t));
  }
  OptimizerOptions options;
  options.backend = OptimizerBackend::nlopt_mma;
  options.max_iterations = 40;
  options.gradient_tolerance = 1e-10;
  options.checkpoint_every = 0;
  const OptimizerResult r =
      minimize(functional, z0, functional.bounds(), functional.margin_constraints(0.02, 0.3), options);
  const int iterations = static_cast<int>(r.history.size()) - 1;
  const double per_iteration = r.seconds / std::max(1, iterations);
  functional.value(r.z);
  std::printf("\nlimit design (square net, x links' R and r, target eps_x = 1.5 eps_y = %.5f):\n", 1.5 * base);
  std::printf("%-12s %10s %12s %14s %16s %12s %12s\n", "status", "iterations", "evaluations", "s/iteration",
              "s/evaluation", "eps_x", "eps_y");
  std::printf("%-12s %10d %12d %14.4f %16.4f %12.6f %12.6f\n", to_string(r.status).c_str(), iterations,
              r.evaluations, per_iteration, median(eval), functional.limits()[0], functional.limits()[1]);
  return {{"status", to_string(r.status)},
          {"iterations", iterations},
          {"evaluations", r.evaluations},
          {"seconds", r.seconds},
          {"seconds_per_iteration", per_iteration},
          {"median_seconds_per_evaluation_with_gradient", median(eval)},
          {"design", {r.z[0], r.z[1]}},
          {"limits", array(functional.limits())},
          {"targets", {targets[0].strain, targets[1].strain}}};
}

double cpu_since(std::clock_t start) { return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC; }

// The chain's uniaxial limit per mesh resolution (see the top of this file).
Json mesh_chain_convergence(const std::vector<int>& segments) {
  const double s0 = 1.5, d_hat = 1e-3;
  const double closed_form = (2.0 * (kRing.major_radius - kRing.minor_radius) - 0.5 * d_hat) / s0 - 1.0;
  LimitOptions options;
  options.max_strain = 0.3;
  options.tolerance = 1e-6;
  std::printf("\nmeshed chain (R = 1, r = 0.2, s0 = 1.5): uniaxial limit per resolution, closed form %.7f\n",
              closed_form);
  std::printf("%10s %10s %12s %12s %12s %12s %8s %12s %10s\n", "segments", "triangles", "limit", "error",
              "bound", "delta", "solves", "cpu s", "crossing");
  Json rows = Json::array();
  for (int major : segments) {
    RigidCellSpec spec = with_torus_meshes(chain_cell(kRing, kRing, s0, 10.0 * s0), major, major / 2);
    spec.activation_distance = d_hat;
    const PeriodicRigidCell cell(spec);
    const std::clock_t c0 = std::clock();
    const LimitPoint p = strain_space_boundary(cell, {uniaxial_path(0.0)}, options)[0];
    const double cpu = cpu_since(c0);
    const double delta = torus_chordal_bound(kRing, major, major / 2);
    const MeshIntersectionReport crossing = check_mesh_intersections(cell, cell.full_state(p.y, p.deformation));
    std::printf("%6d x %-3d %10d %12.7f %12.2e %12.2e %12.2e %8d %12.2f %10ld\n", major, major / 2,
                static_cast<int>(spec.elements[0].mesh->faces.rows()), p.strain, p.strain - closed_form,
                2.0 * delta / s0, delta, p.solves, cpu, crossing.intersecting);
    rows.push_back({{"major_segments", major},
                    {"minor_segments", major / 2},
                    {"triangles_per_ring", spec.elements[0].mesh->faces.rows()},
                    {"locked", p.locked},
                    {"limit", p.strain},
                    {"closed_form", closed_form},
                    {"error", p.strain - closed_form},
                    {"chordal_bound_on_limit", 2.0 * delta / s0},
                    {"solves", p.solves},
                    {"cpu_seconds", cpu},
                    {"intersecting_triangle_pairs", crossing.intersecting}});
  }
  return rows;
}

// The square net's first `directions` principal samples (of 8 over the turn), meshed against the
// implicit tori: median CPU seconds per sample and the limits.
Json mesh_square_net(const std::vector<int>& segments, int directions) {
  RigidCellSpec tori_spec = square_ring_cell(kRing, kRing, kRing, 1.5);
  tori_spec.activation_distance = 1e-3;
  LimitOptions options;
  options.max_strain = 0.3;
  const auto sweep = [&](const RigidCellSpec& spec, std::vector<double>& limits, std::vector<double>& cpu) {
    const PeriodicRigidCell cell(spec);
    const Vector y_rest = rest_equilibrium(cell);
    long crossing = 0;
    for (int k = 0; k < directions; ++k) {
      const std::clock_t c0 = std::clock();
      const LimitPoint p = find_limit(cell, principal_path(2.0 * M_PI * k / 8), y_rest, options);
      cpu.push_back(cpu_since(c0));
      limits.push_back(p.strain);
      if (cell.mesh_contact())
        crossing += check_mesh_intersections(cell, cell.full_state(p.y, p.deformation)).intersecting;
    }
    return crossing;
  };
  std::vector<double> tori_limits, tori_cpu;
  sweep(tori_spec, tori_limits, tori_cpu);
  std::printf("\nsquare ring net, %d principal directions (of 8): meshed rings against implicit tori\n", directions);
  std::printf("%10s %12s %14s %14s %12s %12s %10s\n", "segments", "triangles", "cpu s/sample", "tori cpu s/s.",
              "max |diff|", "bound", "crossing");
  Json rows = Json::array();
  for (int major : segments) {
    std::vector<double> limits, cpu;
    const RigidCellSpec spec = with_torus_meshes(tori_spec, major, major / 2);
    const long crossing = sweep(spec, limits, cpu);
    double diff = 0.0;
    for (std::size_t k = 0; k < limits.size(); ++k) diff = std::max(diff, std::abs(limits[k] - tori_limits[k]));
    const double bound = 2.0 * torus_chordal_bound(kRing, major, major / 2) / 1.5;
    const int triangles = 3 * static_cast<int>(spec.elements[0].mesh->faces.rows());
    std::printf("%6d x %-3d %12d %14.3f %14.4f %12.2e %12.2e %10ld\n", major, major / 2, triangles, median(cpu),
                median(tori_cpu), diff, bound, crossing);
    rows.push_back({{"major_segments", major},
                    {"minor_segments", major / 2},
                    {"cell_triangles", triangles},
                    {"median_cpu_seconds_per_sample", median(cpu)},
                    {"tori_median_cpu_seconds_per_sample", median(tori_cpu)},
                    {"limits", array(limits)},
                    {"tori_limits", array(tori_limits)},
                    {"max_limit_difference", diff},
                    {"chordal_bound_on_limit", bound},
                    {"intersecting_triangle_pairs", crossing}});
  }
  return rows;
}

// Periodic single curvature of the square net along x against disc patches of growing radius.
Json bending_convergence(const std::vector<int>& radii_tenths) {
  const RigidCellSpec net = square_ring_cell(kRing, kRing, kRing, 1.5);
  const PeriodicRigidCell periodic(net);
  const SingleCurvatureCell curved(periodic, 0.0);
  std::clock_t c0 = std::clock();
  const LimitPoint p = find_single_curvature_limit(curved, rest_equilibrium(periodic));
  const double periodic_cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const double periodic_clearance =
      check_clearance(periodic, curved.full_state(p.y, p.strain), 1 << 14).min_lower;
  std::printf("square net, single curvature along x: periodic limit %.10f (%s, refined %d, clearance %.3e, %.2f cpu s)\n",
              p.strain, p.status.c_str(), p.refined, periodic_clearance, periodic_cpu);
  std::printf("%10s %10s %8s %14s %14s %10s %12s %8s\n", "radius", "elements", "free", "limit", "difference",
              "refined", "clearance", "cpu s");
  Json rows = Json::array();
  for (const int tenths : radii_tenths) {
    const double radius = 0.1 * tenths;
    const PeriodicRigidCell patch(disc_patch(net, radius, 1.6));
    int free = 0;
    for (const CellElement& e : patch.spec().elements) free += !e.rim;
    LimitOptions options;
    options.tolerance = 1e-3;
    c0 = std::clock();
    const LimitPoint q = find_limit(patch, uniaxial_path(0.0), rest_equilibrium(patch), options);
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    const double clearance = check_clearance(patch, patch.full_state(q.y, q.deformation), 1 << 14).min_lower;
    std::printf("%10.1f %10d %8d %14.10f %14.10f %10d %12.3e %8.2f\n", radius, patch.num_elements(), free, q.strain,
                q.strain - p.strain, q.refined, clearance, cpu);
    rows.push_back({{"radius", radius},
                    {"elements", patch.num_elements()},
                    {"free_elements", free},
                    {"limit", q.strain},
                    {"locked", q.locked},
                    {"refined", q.refined},
                    {"difference_to_periodic", q.strain - p.strain},
                    {"certified_clearance", clearance},
                    {"cpu_seconds", cpu}});
  }
  return {{"periodic_limit", p.strain},
          {"periodic_refined", p.refined},
          {"periodic_certified_clearance", periodic_clearance},
          {"periodic_cpu_seconds", periodic_cpu},
          {"rim_width", 1.6},
          {"patches", rows}};
}

}  // namespace

int run(int argc, char** argv) {
  int directions = 32;
  int reference_directions = 4;
  std::vector<int> cells = {1, 4, 16};
  std::string out = "bench_interlocking.json";
  std::vector<int> mesh_segments = {12, 16, 24};
  int mesh_directions = 4;
  bool mesh_only = false;
  bench::Cli cli("interlocking_bench", "Strain-space boundaries of interlocking cells and limit design.");
  cli.integer("--directions", directions, "uniaxial directions per boundary", 1);
  cli.integer("--reference-directions", reference_directions,
              "directions (the sweep's first) also run without the broad phase, for the before/after figure", 0);
  cli.integers("--cells", cells, "cells by element count (1, 4 or 16)", 1);
  cli.integers("--mesh-segments", mesh_segments, "mesh bodies: major segments per ring (minor: half; none: 0)", 0);
  cli.integer("--mesh-directions", mesh_directions, "mesh bodies: principal directions of the square net (of 8)", 0);
  cli.flag("--mesh-only", mesh_only, "only the mesh-body tables (no tori cells, no design)");
  bool bending = false;
  std::vector<int> radii_tenths = {31, 46, 61};
  cli.flag("--bending-convergence", bending, "periodic single curvature against disc patches of growing radius");
  cli.integers("--patch-radii", radii_tenths, "disc patch radii in tenths (with --bending-convergence)", 20);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (bending) {
    bench::Json json = bench::report("interlocking_bending_convergence");
    json["bending_convergence"] = bending_convergence(radii_tenths);
    return bench::write_report(out, json, "interlocking_bench") ? 0 : 1;
  }
  for (int c : cells)
    if (c != 1 && c != 4 && c != 16) return cli.usage_error("--cells: 1, 4 or 16");
  for (int m : mesh_segments)
    if (m != 0 && m < 6) return cli.usage_error("--mesh-segments: at least 6 (the minor count is half)");
  bench::Json json = bench::report("interlocking");
  bench::Json boundaries = bench::Json::array();
  if (!mesh_only) {
    std::printf("%8s %6s %10s %12s %12s %12s %12s %8s %8s %10s %12s %10s %10s %14s %14s %6s\n", "elements", "dofs",
                "directions", "s/sample", "cpu s/sample", "s/boundary", "cpu s/bound.", "locked", "refined", "solves", "clearance",
                "min limit", "max limit", "broad cpu (ref)", "all-pairs cpu", "equal");
    for (int c : cells) boundaries.push_back(boundary(c, directions, reference_directions));
    json["boundaries"] = boundaries;
    json["design"] = design();
  }
  mesh_segments.erase(std::remove(mesh_segments.begin(), mesh_segments.end(), 0), mesh_segments.end());
  if (!mesh_segments.empty()) {
    json["mesh_chain"] = mesh_chain_convergence(mesh_segments);
    if (mesh_directions > 0) json["mesh_square_net"] = mesh_square_net(mesh_segments, std::min(mesh_directions, 8));
  }
  return bench::write_report(out, json, "interlocking_bench") ? 0 : 1;
}

}  // namespace tailor::bench::interlocking_bench
