// Newton iteration cost of a discrete elastic rod against its vertex count (should be linear:
// the Hessian is banded). A helical rod with edges of length ~0.01 (length 0.01 (N - 1) for N
// vertices; EI = 1, circular section r = 1e-2) clamped at its first edge sags under gravity
// (weight 2 per unit length; a rod of fixed length 1 would, at 10^5 vertices, start below
// Newton's round-off floor estimate and stop at once); Newton runs a fixed number of
// iterations and the medians of the per-iteration times are reported: assembly (energy,
// gradient, Hessian of the stretching, bending, twisting and load terms), factorization,
// solve, line search, and the whole iteration. Each size runs twice in the same process: with
// the bending and twisting Hessians by dual numbers as before ("duals": the strains' Hessians
// in the edge variables, lifted to the stencil's 11 DOFs) and from cross-edge products
// ("products", forward/rods/cross_edge_products.hpp). Then each term's Hessian request alone
// at the largest size (both ways for bending and twisting). Writes JSON (--out, default
// bench_rods.json) and prints a table.
//
// Second part, rest-shape design (problems/rods/rod_inverse.hpp, the scenes' "inverse" section):
// --strands strands of --strand-vertices vertices (nylon: length 0.5, r = 1e-3, E = 3e9,
// density 1150, clamped at the root, curling up with a radius that differs per strand), each
// designed separately (rest curvatures and rest lengths, target: the drawn shape) by
// --method: "auto" (inverse statics, problems/rods/rod_inverse_statics.hpp, falling back to
// the optimizer) or "optimizer" (Ceres Levenberg-Marquardt; the time until the RMS shape error,
// over the vertices relative to the length, is below --shape-error, read from its history).
// Reports per strand the design time, the scene build time, the time of the forward solve that
// verifies the design (Newton from the drawn shape at the designed rest shape) and the largest
// vertex error of that equilibrium; the median and the total.
//
// usage: rod_bench [--vertices 100,1000,10000,100000] [--iterations N] [--strands S]
//                  [--strand-vertices V] [--shape-error E] [--method auto|optimizer] [--out FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/assembler.hpp"
#include "forward/core/elimination.hpp"
#include "forward/core/statistics.hpp"
#include "forward/fem/loads.hpp"
#include "forward/rods/bending_term.hpp"
#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_supports.hpp"
#include "forward/rods/stretching_term.hpp"
#include "forward/rods/twisting_term.hpp"
#include "forward/solve/newton.hpp"
#include "problems/rods/rod_inverse.hpp"

namespace tailor::bench::rod_bench {

using namespace tailor;

namespace {

struct SizeResult {
  int vertices, free_dofs, iterations;
  int projected;  // iterations whose Hessian was the PSD-projected one (assembled a second time)
  bool product_hessians;
  std::string status;
  double assembly, factorization, solve, line_search, iteration;
};

// The bench's rod: the helix below with its three terms, gravity, the clamp and p.
struct HelixRod {
  std::shared_ptr<DiscreteRod> rod;
  std::unique_ptr<Model> model;
  Vector p, rest;
  RodStretchingTerm* stretching = nullptr;
  RodBendingTerm* bending = nullptr;
  RodTwistingTerm* twisting = nullptr;
};

HelixRod helix_rod(int vertices, bool product_hessians) {
  Eigen::MatrixX3d positions(vertices, 3);
  for (int i = 0; i < vertices; ++i) {
    const double s = 0.01 * i, phi = 4.0 * M_PI * s;  // edges of length ~0.01 at every size
    positions.row(i) << s, 0.05 * std::cos(phi), 0.05 * std::sin(phi);
  }
  HelixRod h;
  h.rod = std::make_shared<DiscreteRod>(positions, 0, 3 * vertices, Eigen::Vector3d::UnitZ());
  const auto& rod = h.rod;
  h.model = std::make_unique<Model>(rod->dof_end());
  Model& model = *h.model;
  RodMaterial material;
  material.radius = 1e-2;
  material.youngs_modulus = 4.0 / (M_PI * std::pow(material.radius, 4));
  material.shear_modulus = material.youngs_modulus / 2.6;
  const RodParameterBlocks blocks = add_rod_parameters(model.parameter_layout(), *rod);
  Vector p = Vector::Zero(model.parameter_layout().size());
  write_rod_parameters(*rod, blocks, material, p);
  h.stretching = &model.add(std::make_unique<RodStretchingTerm>(rod, material.section, blocks));
  h.bending = &model.add(std::make_unique<RodBendingTerm>(rod, material.section, blocks));
  h.twisting = &model.add(std::make_unique<RodTwistingTerm>(rod, material.section, blocks));
  h.bending->set_product_hessian(product_hessians);
  h.twisting->set_product_hessian(product_hessians);
  const double area = M_PI * material.radius * material.radius, g = 9.81;
  const Eigen::VectorXd masses = lumped_vertex_masses(*rod, material.section, 2.0 / (area * g),
                                                      p.segment(blocks.radius, rod->num_edges()),
                                                      p.segment(blocks.rest_length, rod->num_edges()));
  Vector forces = Vector::Zero(model.num_dofs());
  add_gravity_forces(*rod, masses, Eigen::Vector3d(0, -g, 0), forces);
  model.add(std::make_unique<ExternalForceTerm>(forces, "gravity"));
  h.rest = Vector::Zero(model.num_dofs());
  rod->write_rest_state(h.rest);
  model.set_elimination(Elimination::dirichlet(clamped_end_dofs(*rod, RodEnd::first), h.rest));
  h.p = std::move(p);
  return h;
}

SizeResult run(int vertices, int iterations, bool product_hessians) {
  const HelixRod h = helix_rod(vertices, product_hessians);
  const Model& model = *h.model;
  const Vector& p = h.p;
  const Vector& rest = h.rest;
  NewtonOptions options;
  options.max_iterations = iterations;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(rest);
  const NewtonResult r = solver.solve(p, y);
  std::vector<double> assembly, factorization, solve, line_search, iteration;
  int projected = 0;
  for (const auto& it : r.history) {
    projected += it.used_projected ? 1 : 0;
    assembly.push_back(it.assembly_seconds);
    factorization.push_back(it.factorization_seconds);
    solve.push_back(it.solve_seconds);
    line_search.push_back(it.line_search_seconds);
    iteration.push_back(it.assembly_seconds + it.factorization_seconds + it.solve_seconds +
                        it.line_search_seconds);
  }
  return {vertices,         model.elimination().num_free(), r.iterations,  projected, product_hessians,
          to_string(r.status),
          median(assembly), median(factorization),          median(solve), median(line_search),
          median(iteration)};
}

// Process CPU seconds per Hessian request (energy and Hessian values, as Newton's assembly
// asks) of each rod term on the helix of `vertices` vertices, bent and twisted off its rest
// state, medians of `repeats`: the bend-twist terms with Hessians from cross-edge products and
// by dual numbers. CPU time, not wall time: on a loaded machine it does not count the time the
// process waits for a core (with several threads it is their sum).
struct TermTimes {
  double stretching, bending, twisting, bending_dual, twisting_dual;
  double assembler;  // the reduced Hessian (all terms, the gather into the matrix), as Newton's assembly
};

TermTimes time_terms(int vertices, int repeats) {
  const HelixRod h = helix_rod(vertices, true);
  Vector x = h.rest;
  for (int i = 0; i < static_cast<int>(x.size()); ++i) x[i] += 1e-3 * std::sin(0.37 * i);
  auto seconds = [&](const EnergyTerm& term) {
    HessianPattern pattern;
    term.hessian_pattern(pattern);
    std::vector<double> values(pattern.size());
    std::vector<double> times;
    for (int r = 0; r < repeats; ++r) {
      double energy = 0.0;
      EnergyRequest request;
      request.value = &energy;
      request.hessian_values = values.data();
      const std::clock_t c0 = std::clock();
      term.evaluate(x, h.p, request);
      times.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    }
    return median(times);
  };
  TermTimes t{seconds(*h.stretching), seconds(*h.bending), seconds(*h.twisting), 0.0, 0.0, 0.0};
  {
    ReducedAssembler assembler(*h.model);
    SparseMatrix H = assembler.hessian_pattern_matrix();
    const Vector y = h.model->elimination().restrict_state(x);
    std::vector<double> times;
    for (int r = 0; r < repeats; ++r) {
      const std::clock_t c0 = std::clock();
      assembler.evaluate(y, h.p, nullptr, nullptr, &H);
      times.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    }
    t.assembler = median(times);
  }
  h.bending->set_product_hessian(false);
  h.twisting->set_product_hessian(false);
  t.bending_dual = seconds(*h.bending);
  t.twisting_dual = seconds(*h.twisting);
  return t;
}

struct StrandResult {
  int iterations;  // the optimizer's to the stated error, or inverse statics' Gauss-Newton steps
  std::string method;  // that gave the design
  double build_seconds, seconds, verify_seconds, initial_error, error, smallest_pivot;
  double cpu_seconds;  // process CPU time of the design (robust to a loaded machine's preemption)
  std::string status;
};

// Strand k of `strands`: a planar arc of length 0.5 leaving the root horizontally and curling
// up against gravity, radius of curvature 0.3 .. 0.6 (the scene rod_rest_shape_design.json).
nlohmann::json strand_scene(int k, int strands, int vertices, const std::string& method) {
  const double L = 0.5, R = 0.3 + 0.3 * k / std::max(1, strands - 1);
  nlohmann::json points = nlohmann::json::array();
  for (int i = 0; i < vertices; ++i) {
    const double phi = L * i / (vertices - 1) / R;
    points.push_back({R * std::sin(phi), R * (1.0 - std::cos(phi)), 0.0});
  }
  return {{"rods",
           {{{"name", "strand"},
             {"points", points},
             {"cross_section", {{"radius", 1e-3}}},
             {"material", {{"youngs_modulus", 3e9}, {"density", 1150}}},
             {"clamp", {"first"}}}}},
          {"gravity", {0, -9.81, 0}},
          {"inverse",
           {{"design", {"rest_curvature", "rest_length"}},
            {"method", method},
            {"optimizer",
             {{"backend", "ceres_least_squares"},
              {"max_iterations", 50},
              {"objective_tolerance", 0.0},
              {"gradient_tolerance", 1e-20}}}}}};
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One design of strand k. The optimizer's time to the stated error is read from its history:
// J = 1/2 mean |x - t|^2 / L^2, so the RMS shape error is sqrt(2 J). The initial shape error
// (the drawn rest shape under load, a Newton solve of ~40 iterations) is computed after the
// timed part, for the first 10 strands only.
StrandResult design_strand(int k, int strands, int vertices, double shape_error, const std::string& method) {
  auto t0 = std::chrono::steady_clock::now();
  auto problem = build_rod_inverse(strand_scene(k, strands, vertices, method), "strand", "strand");
  StrandResult out{0, "optimizer", seconds_since(t0), -1.0, 0.0, 0.0, 0.0, 0.0, -1.0, "not_reached"};
  StaticFunctional& f = *problem->functional;
  Vector z = problem->z0;
  bool optimize = method == "optimizer";
  if (!optimize) {
    const std::clock_t c0 = std::clock();
    const RodInverseStaticsResult s = solve_rod_inverse_statics(*problem);
    out.cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    out.smallest_pivot = s.stability.smallest_pivot;
    out.iterations = s.steps;  // Gauss-Newton steps
    z = s.z;
    if (s.accepted()) {
      out.method = "inverse_statics";
      out.seconds = s.seconds;
      out.status = "reached";
    } else {
      optimize = true;  // the fallback, from its result
    }
  }
  if (optimize) {
    const auto start = std::chrono::steady_clock::now();
    f.value(z);
    const double setup = seconds_since(start);
    const OptimizerResult r = minimize(f, z, Bounds{}, {}, problem->spec.optimizer);
    out.iterations = static_cast<int>(r.history.size());
    for (const OptimizerIteration& it : r.history)
      if (std::sqrt(2.0 * it.objective) <= shape_error) {
        out.iterations = it.iteration;
        out.seconds = setup + it.seconds;
        out.status = "reached";
        break;
      }
    z = r.z;
  }
  // The check: Newton from the drawn shape (the functional's first solve starts there) at the
  // design; the optimizer's functional warm-starts from its last equilibrium instead.
  t0 = std::chrono::steady_clock::now();
  f.value(z);
  out.verify_seconds = seconds_since(t0);
  out.error = problem->shape_error(f.state());
  out.initial_error = std::nan("");
  if (k < 10) {
    f.value(problem->z0);
    out.initial_error = problem->shape_error(f.state());
  }
  return out;
}

// The bend-twist stencil's strain kernels with Hessians, per stencil (one per interior
// vertex), as many stencils as the largest size (100 to 20,000), on bent, twisted stencils:
// the direct Dual2<11> strains, which the bending and the twisting term each evaluated before
// (twice per stencil), against the terms' present kernels, the curvatures from kb's
// projections in the 6 edge variables and the twist from the reference twist alone, lifted to
// the 11 DOFs. Median over `repeats` passes of seconds per stencil.
struct KernelResult {
  double direct_twice, present;
};

KernelResult time_kernels(int stencils, int repeats) {
  using namespace rod_detail;
  std::vector<BendTwistLocal> locals(static_cast<std::size_t>(stencils));
  StoredFrames frames{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                      Eigen::Vector3d::UnitZ(), 0.0};
  for (int k = 0; k < stencils; ++k) {
    const double a = 0.01 * k;
    BendTwistLocal& l = locals[static_cast<std::size_t>(k)];
    l << 0.0, 0.0, 0.0, 0.01, 0.001 * std::sin(a), 0.0, 0.02, 0.002 * std::cos(a), 0.001, 0.1 * a, 0.1 * a + 0.01;
  }
  double sink = 0.0;
  std::vector<double> direct, present;
  for (int r = 0; r < repeats; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    for (const BendTwistLocal& l : locals)
      for (int term = 0; term < 2; ++term) {
        const auto s = bend_twist_strains<BendTwistDual>(l, frames);
        sink += s.kappa1.h(3, 4) + s.twist.h(0, 7);
      }
    direct.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / stencils);
    t0 = std::chrono::steady_clock::now();
    for (const BendTwistLocal& l : locals) {
      const auto kappa = curvatures_by_edges<Dual2<3>, Dual2<6>, Dual2<kEdgeVariables>>(l, frames);
      const BendTwistDual k1 = lift(kappa[0]), k2 = lift(kappa[1]);
      const BendTwistDual m = twist_from_reference(reference_twist_by_edges<Dual2<3>, Dual2<6>>(l, frames), l);
      sink += k1.h(3, 4) + k2.h(1, 2) + m.h(0, 7);
    }
    present.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / stencils);
  }
  if (sink == 12345.0) std::printf(" ");  // keeps the work
  return {median(direct), median(present)};
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> sizes = {100, 1000, 10000, 100000};
  int iterations = 5;
  std::string out = "bench_rods.json";
  bench::Cli cli("rod_bench", "Newton iteration cost of a discrete elastic rod against its vertex count.");
  cli.integers("--vertices", sizes, "vertex counts of the rod", 3);
  cli.integer("--iterations", iterations, "Newton iterations run (and timed) per size", 1);
  int strands = 10, strand_vertices = 100;
  double shape_error = 1e-6;
  std::string method = "auto";
  cli.integer("--strands", strands, "strands designed (0: no design part)", 0);
  cli.integer("--strand-vertices", strand_vertices, "vertices per strand", 3);
  cli.number("--shape-error", shape_error, "stated RMS shape error (vertex distance / strand length)", 0.0);
  cli.choice("--method", method, "rest-shape design method (the scenes' inverse.method)", {"auto", "optimizer"});
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::vector<SizeResult> results;
  std::printf("%10s %10s %9s %6s %10s %10s %10s %10s %10s %12s %12s %12s\n", "vertices", "free_dofs", "hessians",
              "pr/its", "assembly", "factor", "solve", "line_srch", "iteration", "asm us/vert", "us/vertex",
              "ls us/vertex");
  const KernelResult kernels =
      time_kernels(std::clamp(*std::max_element(sizes.begin(), sizes.end()), 100, 20000), 5);
  std::printf("bend-twist strain kernels with Hessians, per stencil: direct Dual2<11> twice (bending, twisting) "
              "%.2f us, present kernels %.2f us\n",
              1e6 * kernels.direct_twice, 1e6 * kernels.present);
  for (int n : sizes)
    for (bool products : {false, true}) {
      const SizeResult s = run(n, iterations, products);
      results.push_back(s);
      std::printf("%10d %10d %9s %3d/%-2d %10.4f %10.4f %10.4f %10.4f %10.4f %12.3f %12.3f %12.3f\n", s.vertices,
                  s.free_dofs, products ? "products" : "duals", s.projected, s.iterations, s.assembly, s.factorization, s.solve,
                  s.line_search, s.iteration, 1e6 * s.assembly / s.vertices, 1e6 * s.iteration / s.vertices,
                  1e6 * s.line_search / s.vertices);
    }
  const int largest = *std::max_element(sizes.begin(), sizes.end());
  const TermTimes terms = time_terms(largest, 9);
  std::printf("Hessian requests at %d vertices, CPU us per vertex: reduced Hessian %.3f; of it stretching %.3f, bending "
              "%.3f (dual numbers %.3f), twisting %.3f (dual numbers %.3f)\n",
              largest, 1e6 * terms.assembler / largest, 1e6 * terms.stretching / largest, 1e6 * terms.bending / largest,
              1e6 * terms.bending_dual / largest, 1e6 * terms.twisting / largest, 1e6 * terms.twisting_dual / largest);
  bench::Json json = bench::report("rod_newton_iteration");
  // "sizes": one row per size, the present code; "sizes_dual_hessians": the same sizes with the
  // bend-twist Hessians by dual numbers (before the cross-edge products), from the same run.
  bench::Json rows = bench::Json::array(), before = bench::Json::array();
  for (const SizeResult& s : results)
    (s.product_hessians ? rows : before).push_back({{"vertices", s.vertices},
                    {"free_dofs", s.free_dofs},
                    {"iterations", s.iterations},
                    {"projected_iterations", s.projected},
                    {"hessians", s.product_hessians ? "cross_edge_products" : "dual_numbers"},
                    {"status", s.status},
                    {"assembly_s", s.assembly},
                    {"factorization_s", s.factorization},
                    {"solve_s", s.solve},
                    {"line_search_s", s.line_search},
                    {"iteration_s", s.iteration}});
  json["sizes"] = rows;
  json["sizes_dual_hessians"] = before;
  json["term_hessian_cpu_seconds"] = {{"vertices", largest},
                                  {"reduced_hessian", terms.assembler},
                                  {"stretching", terms.stretching},
                                  {"bending", terms.bending},
                                  {"twisting", terms.twisting},
                                  {"bending_dual_numbers", terms.bending_dual},
                                  {"twisting_dual_numbers", terms.twisting_dual}};
  json["stencil_kernels"] = {{"direct_dual2_twice_s", kernels.direct_twice}, {"present_s", kernels.present}};
  if (strands > 0) {
    std::printf("\nrest-shape design (--method %s), %d strands of %d vertices, to a shape error of %.1e of the "
                "length\n",
                method.c_str(), strands, strand_vertices, shape_error);
    std::printf("%8s %16s %6s %11s %11s %11s %11s %11s %11s %12s\n", "strand", "method", "iters", "error0",
                "max_error", "pivot_min", "build_s", "design_s", "verify_s", "status");
    bench::Json designs = bench::Json::array();
    std::vector<double> times, builds, verifies, errors, cpu;
    double total = 0.0;
    for (int k = 0; k < strands; ++k) {
      const StrandResult d = design_strand(k, strands, strand_vertices, shape_error, method);
      if (k < 10 || k == strands - 1)
        std::printf("%8d %16s %6d %11.3e %11.3e %11.3e %11.6f %11.6f %11.6f %12s\n", k, d.method.c_str(),
                    d.iterations, d.initial_error, d.error, d.smallest_pivot, d.build_seconds, d.seconds,
                    d.verify_seconds, d.status.c_str());
      std::fflush(stdout);
      times.push_back(d.seconds);
      builds.push_back(d.build_seconds);
      verifies.push_back(d.verify_seconds);
      errors.push_back(d.error);
      cpu.push_back(d.cpu_seconds);
      total += d.seconds;
      designs.push_back({{"strand", k},
                         {"method", d.method},
                         {"iterations", d.iterations},
                         {"initial_shape_error", d.initial_error},
                         {"shape_error", d.error},
                         {"smallest_pivot", d.smallest_pivot},
                         {"build_seconds", d.build_seconds},
                         {"seconds", d.seconds},
                         {"cpu_seconds", d.cpu_seconds},
                         {"verify_seconds", d.verify_seconds},
                         {"status", d.status}});
    }
    const double worst = *std::max_element(errors.begin(), errors.end());
    std::printf(
        "median %.5f s per strand (process CPU time of inverse statics %.5f s; scene build %.5f s, verifying "
        "forward solve %.5f s), total %.3f s for %d strands, largest shape error %.2e\n",
        median(times), median(cpu), median(builds), median(verifies), total, strands, worst);
    json["rest_shape_design"] = {{"strands", strands},
                                 {"strand_vertices", strand_vertices},
                                 {"method", method},
                                 {"shape_error_target", shape_error},
                                 {"median_seconds_per_strand", median(times)},
                                 {"median_cpu_seconds_per_strand", median(cpu)},
                                 {"median_build_seconds", median(builds)},
                                 {"median_verify_seconds", median(verifies)},
                                 {"total_seconds", total},
                                 {"largest_shape_error", worst},
                                 {"strand_results", designs}};
  }
  return bench::write_report(out, json, "rod_bench") ? 0 : 1;
}

}  // namespace tailor::bench::rod_bench
