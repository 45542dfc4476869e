#include "problems/metamaterial/metamaterial_scene.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <random>
#include <sstream>

#include "forward/core/format_number.hpp"
#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/fem/scene.hpp"
#include "problems/homogenization/directional_plots.hpp"
#include "problems/homogenization/homogenize_command.hpp"
#include "problems/json_text.hpp"
#include "problems/optimizer_section.hpp"
#include "problems/plot/field_image.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

MetamaterialDesignSpec parse_metamaterial_design(const SceneNode& root, const CellScene& scene) {
  const SceneNode design = root.at("design");
  design.expect_keys({"material", "filter_radius", "max_volume_fraction", "initial_density", "perturbation",
                      "projection", "seed", "objective", "optimizer", "refine"});
  MetamaterialDesignSpec spec;
  const SceneNode material = design.at("material");
  material.expect_keys({"youngs_modulus", "poisson_ratio", "min_youngs_modulus", "penalty"});
  spec.material.youngs_modulus = material.at("youngs_modulus").positive();
  spec.material.poisson_ratio = material.at("poisson_ratio").open_interval(-1.0, 0.5);
  if (material.has("min_youngs_modulus"))
    spec.material.min_youngs_modulus = material.at("min_youngs_modulus").positive();
  if (material.has("penalty")) spec.material.penalty = material.at("penalty").positive();
  spec.filter_radius = design.at("filter_radius").positive();
  {
    double shortest = 1e300;  // the density filter's limit (problems/metamaterial/density_filter.hpp)
    for (int k = 0; k < scene.cell.dim(); ++k) shortest = std::min(shortest, scene.cell.lattice.col(k).norm());
    if (spec.filter_radius > 0.5 * shortest)
      design.at("filter_radius")
          .fail("at most half the shortest lattice vector (" + format_number(0.5 * shortest) +
                "): a wider filter would reach the same element through two periodic images");
  }
  spec.max_volume_fraction = design.at("max_volume_fraction").open_interval(0.0, 1.0 + 1e-12);
  for (const SceneNode& v : design.at("initial_density").items())
    spec.initial_density.push_back(v.open_interval(-1e-12, 1.0 + 1e-12));
  if (spec.initial_density.size() != scene.materials.size())
    design.at("initial_density").fail("need one initial density per material of the cell");
  if (design.has("perturbation")) spec.perturbation = design.at("perturbation").non_negative();
  if (design.has("seed")) spec.seed = static_cast<unsigned>(design.at("seed").integer(0));
  if (design.has("refine")) spec.refine = design.at("refine").integer(1);
  if (const auto projection = design.find("projection")) {
    spec.projection_betas.clear();
    for (const SceneNode& b : projection->items()) spec.projection_betas.push_back(b.non_negative());
    if (spec.projection_betas.empty()) projection->fail("need at least one beta (0: no projection)");
  }

  const int dim = scene.cell.dim();
  const SceneNode objective = design.at("objective");
  objective.expect_keys({"poisson_ratio", "directional_stiffness", "entries"});
  if (const auto poisson = objective.find("poisson_ratio")) {
    poisson->expect_keys({"target", "weight", "pairs"});
    spec.objective.poisson_target = poisson->at("target").open_interval(-1.0, 1.0);
    if (poisson->has("weight")) spec.objective.poisson_weight = poisson->at("weight").positive();
    for (const SceneNode& pair : poisson->at("pairs").items()) {
      const std::vector<SceneNode> dn = pair.items();
      if (dn.size() != 2) pair.fail("expected [d, n]");
      spec.objective.poisson_pairs.emplace_back(dn[0].vector(dim), dn[1].vector(dim));
    }
  }
  if (const auto stiffness = objective.find("directional_stiffness")) {
    stiffness->expect_keys({"directions", "targets", "weight"});
    for (const SceneNode& d : stiffness->at("directions").items())
      spec.objective.directions.push_back(d.vector(dim));
    for (const SceneNode& t : stiffness->at("targets").items())
      spec.objective.target_moduli.push_back(t.positive());
    if (spec.objective.directions.size() != spec.objective.target_moduli.size())
      stiffness->fail("need one target per direction");
    if (stiffness->has("weight")) spec.objective.directional_weight = stiffness->at("weight").positive();
  }
  if (const auto entries = objective.find("entries")) {
    entries->expect_keys({"values", "scale"});
    const int m = voigt_size(dim);
    for (const SceneNode& e : entries->at("values").items()) {
      e.expect_keys({"row", "col", "value", "weight"});
      CellObjective::Entry entry{e.at("row").integer(0), e.at("col").integer(0), e.at("value").number(), 1.0};
      if (entry.row >= m || entry.col >= m) e.fail("Voigt indices must be below " + std::to_string(m));
      if (e.has("weight")) entry.weight = e.at("weight").positive();
      spec.objective.entries.push_back(entry);
    }
    if (entries->has("scale")) spec.objective.entry_scale = entries->at("scale").positive();
  }
  if (spec.objective.entries.empty() && spec.objective.directions.empty() &&
      spec.objective.poisson_pairs.empty())
    objective.fail("no objective given");

  OptimizerOptions defaults;
  defaults.backend = OptimizerBackend::nlopt_mma;
  defaults.max_iterations = 100;
  defaults.gradient_tolerance = 0.0;
  defaults.objective_tolerance = 1e-9;
  spec.optimizer = defaults;
  if (const auto optimizer = design.find("optimizer")) {
    OptimizerSectionSupport support;
    support.kind = "a cell design";
    support.needs.bounds = support.needs.inequality_constraints = true;  // densities in [0, 1], volume
    spec.optimizer = parse_optimizer_section(*optimizer, defaults, support);
  }
  const SceneNode cell = root.at("cell");
  if (cell.has("grid")) spec.grid = cell.at("grid").integers(1);
  if (cell.has("split")) spec.split = cell.at("split").string();
  // The refined check solves a periodic cell of refine^dim times the design mesh's elements after
  // the optimization: refused here, before it, when that would not be a check but a long solve
  // that runs out of memory (refine 50 on a 2D cell grew to 3.3 GB).
  if (spec.refine > 1 && !spec.grid.empty()) {
    const double refined = static_cast<double>(scene.cell.mesh.num_elements()) * std::pow(spec.refine, dim);
    if (refined > kMaxRefinedElements)
      design.at("refine").fail("the refined check would solve a cell of " + format_number(refined, "%.3g") +
                               " elements (the design mesh's " + std::to_string(scene.cell.mesh.num_elements()) +
                               " times refine^" + std::to_string(dim) + "); at most " +
                               format_number(kMaxRefinedElements, "%.3g") + ": take a smaller refine");
  }
  return spec;
}

namespace {

// Thresholded densities of a fine grid cell (each coarse grid parallelogram split into
// refine^dim fine ones) from a coarse per-element density, by locating fine centroids in the
// coarse elements of their grid parallelogram.
Vector refine_density(const PeriodicCell& coarse, const Mesh& fine, const Vector& coarse_density,
                      const std::vector<int>& grid) {
  const int dim = coarse.dim();
  const Eigen::MatrixXd inverse = coarse.lattice.inverse();
  int per_cell = coarse.mesh.num_elements();
  for (const int n : grid) per_cell /= n;
  Vector out(fine.num_elements());
  for (int e = 0; e < fine.num_elements(); ++e) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(dim);
    for (int a = 0; a <= dim; ++a) c += fine.rest_positions.row(fine.elements(e, a)).transpose();
    c /= dim + 1;
    const Eigen::VectorXd f = inverse * (c - coarse.origin);
    int index = 0;
    for (int k = dim - 1; k >= 0; --k)
      index = index * grid[k] + std::clamp(static_cast<int>(f[k] * grid[k]), 0, grid[k] - 1);
    double value = coarse_density[per_cell * index];
    for (int t = 0; t < per_cell; ++t) {
      const int ce = per_cell * index + t;
      Eigen::MatrixXd T(dim, dim);
      const Eigen::VectorXd p0 = coarse.mesh.rest_positions.row(coarse.mesh.elements(ce, 0)).transpose();
      for (int a = 0; a < dim; ++a)
        T.col(a) = coarse.mesh.rest_positions.row(coarse.mesh.elements(ce, a + 1)).transpose() - p0;
      const Eigen::VectorXd b = T.inverse() * (c - p0);
      if ((b.array() >= -1e-12).all() && b.sum() <= 1.0 + 1e-12) {
        value = coarse_density[ce];
        break;
      }
    }
    out[e] = value;
  }
  return out;
}

nlohmann::json summary_json(const CellObjective& objective, const Matrix& C) {
  const Matrix S = compliance(C);
  const int dim = C.rows() == 3 ? 2 : 3;
  nlohmann::json out = {{"objective", objective.evaluate(C, nullptr)}, {"stiffness", matrix_json(C)}};
  out["youngs_modulus_x"] = directional_youngs_modulus(S, plane_direction(dim, 0, 1, 0.0));
  out["youngs_modulus_y"] = directional_youngs_modulus(S, plane_direction(dim, 0, 1, M_PI / 2));
  out["poisson_ratio_xy"] =
      poisson_ratio(S, plane_direction(dim, 0, 1, 0.0), plane_direction(dim, 0, 1, M_PI / 2));
  out["poisson_ratio_yx"] =
      poisson_ratio(S, plane_direction(dim, 0, 1, M_PI / 2), plane_direction(dim, 0, 1, 0.0));
  nlohmann::json poisson = nlohmann::json::array(), moduli = nlohmann::json::array();
  for (const auto& [d, n] : objective.poisson_pairs) poisson.push_back(poisson_ratio(S, d, n));
  for (const auto& d : objective.directions) moduli.push_back(directional_youngs_modulus(S, d));
  out["objective_poisson_ratios"] = poisson;
  out["objective_directional_moduli"] = moduli;
  return out;
}

}  // namespace

MetamaterialRun run_metamaterial_design(const CellScene& scene, const MetamaterialDesignSpec& spec,
                                        const std::string& out_dir, std::ostream* log,
                                        std::ostream* progress) {
  auto cell = std::make_shared<LinearCell>(scene.cell, scene.plane);
  CellDesignFunctional functional(cell, spec.material, spec.filter_radius, spec.objective);

  const int ne = cell->num_elements();
  Vector z0(ne);
  std::mt19937 rng(spec.seed);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  for (int e = 0; e < ne; ++e)
    z0[e] =
        std::clamp(spec.initial_density[scene.element_phase[e]] + spec.perturbation * noise(rng), 0.0, 1.0);
  Bounds bounds{Vector::Zero(ne), Vector::Ones(ne)};
  Constraint volume{"volume_fraction", false, [&](const Vector& z, Vector* g) {
                      return functional.volume_fraction(z, g) - spec.max_volume_fraction;
                    }};
  OptimizerOptions options = spec.optimizer;
  options.progress = progress;
  if (log)
    *log << "designing " << scene.name << ": " << ne << " elements, filter radius " << spec.filter_radius
         << " (minimum length), volume fraction <= " << spec.max_volume_fraction << ", "
         << to_string(options.backend) << "\n";
  MetamaterialRun run;
  // Continuation on the projection sharpness: one optimizer run per beta, each from the last.
  Vector z = z0;
  std::vector<OptimizerIteration> stages;
  double seconds = 0.0;
  for (const double beta : spec.projection_betas) {
    functional.set_projection(beta);
    // A time limit is the whole continuation's: each stage gets what the earlier ones left.
    if (spec.optimizer.time_limit_seconds > 0.0) {
      options.time_limit_seconds = spec.optimizer.time_limit_seconds - seconds;
      if (options.time_limit_seconds <= 0.0) break;  // not the first stage: the limit is positive
    }
    run.result = minimize(functional, z, bounds, {volume}, options);
    for (auto it : run.result.history) {
      it.iteration = static_cast<int>(stages.size());
      it.seconds += seconds;
      stages.push_back(it);
    }
    seconds += run.result.seconds;
    z = run.result.z;
    if (log)
      *log << "  beta " << beta << ": " << to_string(run.result.status) << " after "
           << run.result.history.size() << " iterations, J = " << run.result.objective << "\n";
  }
  run.result.history = stages;
  run.result.seconds = seconds;

  // Final (filtered, projected SIMP) design, then thresholded at 1/2 on the design mesh and on a refined
  // grid.
  functional.value(run.result.z);
  run.stiffness_gray = functional.last().stiffness;
  const Vector rho = functional.densities(run.result.z);
  Vector solid(ne);
  for (int e = 0; e < ne; ++e) solid[e] = rho[e] >= 0.5 ? 1.0 : 0.0;
  const Vector nu0 = Vector::Constant(ne, spec.material.poisson_ratio);
  const LinearHomogenization thresholded = cell->solve(functional.youngs_moduli(solid), nu0);
  run.stiffness_thresholded = thresholded.stiffness;
  std::filesystem::create_directories(out_dir);
  nlohmann::json refined_json = nullptr;  // after the design's files are written (below)
  run.objective_gray = spec.objective.evaluate(run.stiffness_gray, nullptr);
  run.objective_thresholded = spec.objective.evaluate(run.stiffness_thresholded, nullptr);

  nlohmann::ordered_json report;
  add_report_header(report);
  report["status"] = to_string(run.result.status);
  report["message"] = run.result.message;
  report["scene"] = scene.name;
  report["backend"] = to_string(options.backend);
  report["filter_radius"] = spec.filter_radius;
  report["projection_betas"] = spec.projection_betas;
  report["max_volume_fraction"] = spec.max_volume_fraction;
  report["volume_fraction"] = functional.volume_fraction(run.result.z, nullptr);
  report["gray"] = summary_json(spec.objective, run.stiffness_gray);
  report["thresholded"] = summary_json(spec.objective, run.stiffness_thresholded);
  report["thresholded"]["volume_fraction"] =
      element_volumes(scene.cell.mesh).dot(solid) / scene.cell.volume();
  report["refined_thresholded"] = refined_json;
  nlohmann::json history = nlohmann::json::array();
  for (const auto& it : run.result.history)
    history.push_back({{"iteration", it.iteration},
                       {"objective", it.objective},
                       {"gradient_norm", it.gradient_norm},
                       {"seconds", it.seconds}});
  report["history"] = history;
  report["seconds"] = run.result.seconds;
  const FunctionalCounters& counters = functional.counters();
  report["timings"] = {{"evaluations", counters.evaluations},
                       {"forward_seconds", counters.forward_seconds},
                       {"adjoint_seconds", counters.adjoint_seconds},
                       {"seconds_per_evaluation", (counters.forward_seconds + counters.adjoint_seconds) /
                                                      std::max(1, counters.evaluations)}};
  const std::string report_path = write_report(out_dir, report);

  VtkFields fields;
  fields.cell["design"] = run.result.z;
  fields.cell["density"] = rho;
  fields.cell["thresholded"] = solid;
  write_vtu(out_dir + "/design.vtu", scene.cell.mesh, fields);
  // E(d) and nu(d) of the thresholded design on the design mesh.
  write_directional_plots(out_dir, scene.name + " (thresholded)",
                          sample_directions(compliance(run.stiffness_thresholded), scene.directions));
  FieldImageOptions picture;
  picture.title = scene.name + ": designed cell";
  picture.bar_label = "density";
  write_field_png(out_dir + "/design.png", scene.cell.mesh,
                  {{"physical density", rho}, {"thresholded at 1/2", solid}}, picture);
  // The refined check last: the design, its report and pictures are on disk before this solve,
  // the largest of the run, starts (a run killed or out of memory here keeps them).
  if (!spec.grid.empty() && spec.refine > 1) {
    std::vector<int> fine_grid;
    for (const int n : spec.grid) fine_grid.push_back(n * spec.refine);
    const Mesh fine = scene.cell.dim() == 2
                          ? lattice_triangle_mesh(scene.cell.lattice, scene.cell.origin, fine_grid[0],
                                                  fine_grid[1], parse_triangle_split(spec.split))
                          : lattice_tet_mesh(scene.cell.lattice, scene.cell.origin, fine_grid[0],
                                             fine_grid[1], fine_grid[2]);
    LinearCell fine_cell(make_periodic_cell(fine, scene.cell.lattice, scene.cell.origin), scene.plane);
    const Vector fine_solid = refine_density(scene.cell, fine, solid, spec.grid);
    const LinearHomogenization refined =
        fine_cell.solve(functional.youngs_moduli(fine_solid),
                        Vector::Constant(fine.num_elements(), spec.material.poisson_ratio));
    run.stiffness_refined = refined.stiffness;
    refined_json = summary_json(spec.objective, refined.stiffness);
    refined_json["elements"] = fine.num_elements();
  }
  if (run.stiffness_refined.size()) {
    run.objective_refined = spec.objective.evaluate(run.stiffness_refined, nullptr);
    report["refined_thresholded"] = refined_json;
    write_report(out_dir, report);
  }
  if (log)
    *log << "status " << to_string(run.result.status) << " after " << run.result.history.size()
         << " iterations (" << run.result.seconds << " s)\n"
         << "gray design:        " << dump_json(report["gray"]) << "\n"
         << "thresholded (1/2):  " << dump_json(report["thresholded"]) << "\n"
         << "refined x" << spec.refine << ":        " << dump_json(refined_json) << "\n"
         << "wrote " << report_path << ", design.vtu, design.png and the thresholded design's "
         << "youngs_modulus_polar.png and poisson_ratio.png\n";
  return run;
}

}  // namespace tailor
