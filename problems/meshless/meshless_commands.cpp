#include "problems/meshless/meshless_commands.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>

#include "adjoint/taylor_test.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/solve/newton.hpp"
#include "problems/json_text.hpp"
#include "problems/meshless/meshless_runs.hpp"
#include "problems/meshless/meshless_vtu.hpp"
#include "problems/optimizer_report.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {

namespace {

std::unique_ptr<MeshlessScene> load_meshless(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  MeshlessSceneSpec spec = parse_meshless_scene(root, options.directory);
  spec.name = options.name;
  auto scene = build_meshless_scene(spec);
  if (log)
    *log << "meshless " << spec.name << ": " << scene->num_nodes() << " nodes, " << scene->quadrature->num_points()
         << " quadrature points (volume " << scene->sampling.volume() << "), " << scene->samples.rows()
         << " output samples; largest moment-matrix condition " << scene->quadrature->max_condition << "\n";
  return scene;
}

// The covering and conditioning of the quadrature (docs/meshless.md, "Nodes and quadrature").
nlohmann::ordered_json meshless_discretization_json(const MeshlessScene& S) {
  int fewest = S.num_nodes();
  for (int q = 0; q < S.quadrature->num_points(); ++q) fewest = std::min(fewest, S.quadrature->size(q));
  nlohmann::ordered_json j = {{"nodes", S.num_nodes()},
                              {"quadrature_points", S.quadrature->num_points()},
                              {"volume", S.sampling.volume()},
                              {"cells_inside", S.sampling.cells_inside},
                              {"cells_cut", S.sampling.cells_cut},
                              {"cells_refined", S.sampling.cells_refined},
                              {"finest_node_level", S.sampling.level.maxCoeff()},
                              {"covering", {{"points", S.covering.points},
                                            {"points_repaired", S.covering.points_repaired},
                                            {"nodes_enlarged", S.covering.nodes_enlarged},
                                            {"largest_support_growth", S.covering.largest_growth},
                                            {"passes", S.covering.passes}}},
                              {"leaves_cut", S.sampling.leaves_cut},
                              {"fewest_covering_nodes", fewest},
                              {"basis_size", S.mls->basis_size()},
                              {"largest_condition", S.quadrature->max_condition},
                              {"seconds", {{"implicit_surface", S.seconds_implicit},
                                           {"octree", S.seconds_sampling},
                                           {"shape_functions_and_quadrature", S.seconds_quadrature}}}};
  if (S.surface) {
    const ImplicitSurfaceReport& r = S.surface->report();
    j["implicit_surface"] = {{"samples", r.samples},
                             {"neighbour_distance", r.neighbour_distance},
                             {"support_radius", r.support_radius},
                             {"fewest_neighbours", r.min_neighbours},
                             {"quadric_fits", r.quadric_fits},
                             {"linear_fits", r.linear_fits},
                             {"largest_boundary_gap_degrees", r.max_boundary_gap * 180.0 / M_PI}};
  }
  return j;
}

void write_meshless_fields(const MeshlessFields& f, const MeshlessScene& S, const std::filesystem::path& dir) {
  const int n = S.num_nodes();
  Eigen::VectorXd region(n);
  for (int a = 0; a < n; ++a) region[a] = S.region_of_node[static_cast<std::size_t>(a)];
  write_points_vtu((dir / "nodes.vtu").string(), S.sampling.nodes,
                   {{"displacement", 3, as_interleaved(f.displacement)},
                    {"coefficient_displacement", 3, as_interleaved(f.coefficient_displacement)},
                    {"youngs_modulus", 1, f.youngs_modulus},
                    {"region", 1, region},
                    {"node_level", 1, S.sampling.level.cast<double>()},
                    {"support_radius", 1, S.mls->options().support_factor * S.patch_spacing}});
  write_points_vtu((dir / "samples.vtu").string(), S.samples, {{"displacement", 3, as_interleaved(f.sample_displacement)}});
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

MeshlessDesign load_meshless_design(const SceneNode& root, const MeshlessVerbOptions& options, const std::string& verb,
                                    std::ostream* log) {
  MeshlessDesign design;
  design.scene = load_meshless(root, options, log);
  if (!design.scene->spec.inverse)
    throw SceneError(design.scene->spec.source + ": " + verb + " needs an \"inverse\" section");
  design.inverse = build_meshless_inverse(*design.scene);
  return design;
}

MeshlessSimulation simulate_meshless(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  const auto scene = load_meshless(root, options, log);
  const MeshlessScene& S = *scene;
  NewtonOptions newton;
  newton.max_iterations = S.spec.max_newton_iterations;
  newton.reuse_factorization = S.spec.reuse_factorization;
  NewtonSolver solver(*S.model, newton);
  Vector y = S.model->elimination().restrict_state(S.rest());
  const NewtonResult r = solver.solve(S.p, y);
  const Vector x = S.model->elimination().expand(y);
  const std::filesystem::path dir(options.out_dir);
  std::filesystem::create_directories(dir);
  MeshlessSimulation out{r.converged(), meshless_fields(S, meshless_node_values(S), x, S.p)};
  write_meshless_fields(out.fields, S, dir);
  double largest = 0.0;
  for (Eigen::Index i = 0; i < out.fields.sample_displacement.rows(); ++i)
    largest = std::max(largest, out.fields.sample_displacement.row(i).norm());
  nlohmann::ordered_json report;
  report["scene"] = S.spec.name;
  report["discretization"] = meshless_discretization_json(S);
  report["converged"] = r.converged();
  report["newton"] = {{"status", r.message},
                      {"iterations", r.iterations},
                      {"final_residual", r.final_residual},
                      {"seconds", r.total_seconds},
                      {"reuse_factorization", to_string(S.spec.reuse_factorization)},
                      {"factorizations", r.factorizations()},
                      {"kept_factor_steps", r.kept_factor_steps()},
                      {"cg_iterations", r.cg_iterations()}};
  report["max_sample_displacement"] = largest;
  const std::string path = write_report(options.out_dir, report);
  if (log)
    *log << (r.converged() ? "converged" : "NOT converged") << " after " << r.iterations << " Newton iterations; largest sample displacement "
         << largest << "\nwrote " << path << ", nodes.vtu and samples.vtu\n";
  return out;
}

bool simulate_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  return simulate_meshless(root, options, log).converged;
}

bool modes_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  compute_meshless_modes(root, options, log);
  return true;
}

MeshlessModes compute_meshless_modes(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  const auto scene = load_meshless(root, options, log);
  // With handles the modes leave the handles' nodes free (the fixed boxes alone held): the
  // handles act in the warped dynamics as springs.
  if (scene->fixed_elimination) scene->model->set_elimination(*scene->fixed_elimination);
  const MeshlessScene& S = *scene;
  const MeshlessSceneSpec& spec = S.spec;
  ModalAnalysisOptions modal;
  modal.count = options.count > 0 ? options.count : spec.mode_count;
  const auto t0 = std::chrono::steady_clock::now();
  const SparseMatrix mass = meshless_mass_matrix(*S.quadrature, spec.density);
  ModalAnalysis m;
  try {
    m = modal_analysis(*S.model, 3, S.rest(), S.p, mass, modal);
  } catch (const std::exception& e) {
    throw SceneError(spec.source + ": modal analysis failed: " + e.what());
  }
  const double modal_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::filesystem::path dir(options.out_dir);
  std::filesystem::create_directories(dir);
  // Evaluation points: the samples, the point of modes.force, the handles' nodes.
  Eigen::MatrixXd points = S.samples;
  if (spec.modal_force) {
    points.conservativeResize(points.rows() + 1, 3);
    points.row(points.rows() - 1) = spec.modal_force->at.transpose();
  }
  const int force_point = static_cast<int>(points.rows()) - 1;
  std::vector<ModalHandle> handles;
  for (const MeshlessScene::Handle& h : S.handles) {
    ModalHandle handle;
    handle.displacements.resize(static_cast<Eigen::Index>(h.nodes.size()), 3);
    handle.rotation = h.rotation;
    handle.rotation_weight = 0.0;
    for (std::size_t i = 0; i < h.nodes.size(); ++i) {
      const Eigen::Vector3d X = S.sampling.nodes.row(h.nodes[i]).transpose();
      handle.points.push_back(static_cast<int>(points.rows()));
      points.conservativeResize(points.rows() + 1, 3);
      points.row(points.rows() - 1) = X.transpose();
      handle.displacements.row(static_cast<Eigen::Index>(i)) = h.targets.row(static_cast<Eigen::Index>(i)) - X.transpose();
      handle.rotation_weight += (X - h.center).squaredNorm() / static_cast<double>(h.nodes.size());
    }
    if (!(handle.rotation_weight > 0.0)) handle.rotation_weight = S.size() * S.size();
    handles.push_back(std::move(handle));
  }
  // With handles the rigid modes (zero stiffness, held by the handles' springs) join the modes.
  Eigen::MatrixXd modes = m.modes;
  Eigen::VectorXd eigenvalues = m.eigenvalues;
  if (!handles.empty() && m.rigid_modes.cols() > 0) {
    modes.resize(m.modes.rows(), m.rigid_modes.cols() + m.modes.cols());
    modes << m.rigid_modes, m.modes;
    eigenvalues.resize(modes.cols());
    eigenvalues << Eigen::VectorXd::Zero(m.rigid_modes.cols()), m.eigenvalues;
  }
  ModalWarpingOperators ops;
  try {
    ops = modal_warping_operators(*S.mls, modes, points);
  } catch (const MeshlessPointError& e) {
    throw SceneError(spec.source + ": modes.force.at: " + e.what());
  }
  std::vector<PointArray> arrays;
  const Eigen::Index first_elastic = modes.cols() - m.modes.cols();  // after the rigid modes handles add
  for (Eigen::Index j = 0; j < m.modes.cols(); ++j)
    arrays.push_back(
        {"mode_" + std::to_string(j + 1), 3, ops.displacement.col(first_elastic + j).head(3 * S.samples.rows())});
  write_points_vtu((dir / "modes.vtu").string(), S.samples, arrays);

  nlohmann::ordered_json report;
  report["scene"] = spec.name;
  report["discretization"] = meshless_discretization_json(S);
  report["modal_analysis_seconds"] = modal_seconds;
  report["frequencies"] = to_json(m.frequencies);
  Vector ratios(m.eigenvalues.size());
  for (Eigen::Index j = 0; j < ratios.size(); ++j) ratios[j] = spec.damping.ratio(m.eigenvalues[j]);
  report["rayleigh"] = {{"alpha", spec.damping.alpha}, {"beta", spec.damping.beta}};
  report["damping_ratios"] = to_json(ratios);
  report["rigid_modes"] = m.rigid_modes.cols();
  if (log) *log << "frequencies [Hz]: " << m.frequencies.transpose() << "\n";
  MeshlessModes out;
  out.frequencies = m.frequencies;
  out.eigenvalues = m.eigenvalues;
  out.damping_ratios = ratios;
  out.rest_positions = S.sampling.nodes;
  out.node_modes = meshless_node_values(S) * m.modes;
  out.samples = S.samples;
  out.sample_modes = ops.displacement.middleCols(first_elastic, m.modes.cols()).topRows(3 * S.samples.rows());
  out.rigid_modes = static_cast<int>(m.rigid_modes.cols());
  if (spec.steps > 0) {
    if (!spec.modal_force && handles.empty()) throw SceneError(spec.source + ": modes.steps: needs modes.force or handles");
    // Handle springs stiffer than every mode by modes.handle_stiffness (default 1e4: their
    // targets are met to ~1e-4 of the elastic response; docs/meshless.md, "Modal warping").
    const double handle_stiffness = spec.handle_stiffness * eigenvalues.cwiseAbs().maxCoeff();
    std::unique_ptr<WarpedModalSimulator> simulator;
    try {
      simulator = std::make_unique<WarpedModalSimulator>(ops, eigenvalues, spec.damping, spec.time_step, handles, handle_stiffness);
    } catch (const std::invalid_argument& e) {
      throw SceneError(spec.source + ": handles: " + e.what());
    }
    WarpedModalSimulator& sim = *simulator;
    const int at = force_point, samples = static_cast<int>(S.samples.rows());
    std::vector<std::pair<double, std::string>> frames;
    std::vector<double> step_seconds;
    std::filesystem::create_directories(dir / "frames");
    Eigen::VectorXd u, linear;
    double largest_rotation = 0.0;
    for (int k = 1; k <= spec.steps; ++k) {
      const auto s0 = std::chrono::steady_clock::now();
      const Eigen::VectorXd f = spec.modal_force && k <= spec.steps / 2 ? sim.modal_force(at, spec.modal_force->force)
                                                                        : Eigen::VectorXd::Zero(sim.num_modes());
      sim.step(f);
      sim.displacements(u, true);
      step_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count());
      const Eigen::VectorXd w = ops.rotation * sim.amplitudes();
      for (Eigen::Index i = 0; i < w.size() / 3; ++i) largest_rotation = std::max(largest_rotation, w.segment<3>(3 * i).norm());
      if (k % spec.frame_every == 0 || k == spec.steps) {
        sim.displacements(linear, false);
        const std::string name = "frames/frame_" + std::to_string(k) + ".vtu";
        write_points_vtu((dir / name).string(), S.samples,
                         {{"displacement", 3, u.head(3 * samples)}, {"linear_displacement", 3, linear.head(3 * samples)}});
        frames.emplace_back(k * spec.time_step, name);
      }
    }
    write_pvd((dir / "result.pvd").string(), frames);
    // The handles' errors at the last step: warped displacement against the target, rotation
    // vector against the handle's.
    double handle_position_error = 0.0, handle_rotation_error = 0.0;
    const Eigen::VectorXd w_end = ops.rotation * sim.amplitudes();
    for (const ModalHandle& h : handles)
      for (std::size_t i = 0; i < h.points.size(); ++i) {
        const Eigen::Index row = 3 * static_cast<Eigen::Index>(h.points[i]);
        handle_position_error = std::max(handle_position_error,
                                         (u.segment<3>(row) - h.displacements.row(static_cast<Eigen::Index>(i)).transpose()).norm());
        handle_rotation_error = std::max(handle_rotation_error, (w_end.segment<3>(row) - *h.rotation).norm());
      }
    double final_smallest = std::numeric_limits<double>::infinity(), final_largest = 0.0;
    for (Eigen::Index i = 0; i < samples; ++i) {
      final_smallest = std::min(final_smallest, w_end.segment<3>(3 * i).norm());
      final_largest = std::max(final_largest, w_end.segment<3>(3 * i).norm());
    }
    report["warped_dynamics"] = {{"steps", spec.steps},
                                 {"final_rotation_angles", {final_smallest, final_largest}},
                                 {"handles", handles.size()},
                                 {"handle_position_error", handle_position_error},
                                 {"handle_rotation_error", handle_rotation_error},
                                 {"handle_stiffness", handle_stiffness},
                                 {"time_step", spec.time_step},
                                 {"frames", frames.size()},
                                 {"median_seconds_per_step", median_of(step_seconds)},
                                 {"largest_rotation_angle", largest_rotation}};
    if (log)
      *log << spec.steps << " warped modal steps (" << m.modes.cols() << " modes, " << samples << " samples): median "
           << median_of(step_seconds) * 1e3 << " ms per step, largest rotation " << largest_rotation << " rad; wrote result.pvd\n";
  }
  const std::string path = write_report(options.out_dir, report);
  if (log) *log << "wrote " << path << " and modes.vtu\n";
  return out;
}

bool gradcheck_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  const MeshlessDesign design = load_meshless_design(root, options, "gradcheck", log);
  const MeshlessScene* scene = design.scene.get();
  const MeshlessInverse* inverse = design.inverse.get();
  TaylorTestOptions taylor;
  taylor.seed = options.seed.value_or(scene->spec.inverse->seed);
  const TaylorTestResult gradient = taylor_test(*inverse->functional, inverse->z0, taylor);
  if (log) *log << "gradient of the observation misfit in " << inverse->z0.size() << " design variables\n" << gradient.table();
  std::optional<TaylorTestResult> hessian;
  if (options.hessian) {
    hessian = taylor_test_hessian(*inverse->functional, inverse->z0, taylor);
    if (log) *log << "Hessian-vector products:\n" << hessian->table();
  }
  std::filesystem::create_directories(options.out_dir);
  nlohmann::ordered_json document = taylor_json(gradient);
  add_report_header(document);
  document["scene"] = scene->spec.name;
  document["design_size"] = inverse->z0.size();
  document["seed"] = taylor.seed;
  if (hessian) document["hessian"] = taylor_json(*hessian);
  write_report_file((std::filesystem::path(options.out_dir) / "gradcheck.json").string(), document);
  const bool passed = gradient.passed() && (!hessian || hessian->passed());
  if (log) *log << (passed ? "passed" : "FAILED") << ": " << gradient.message << "\n";
  return passed;
}

MeshlessRun run_meshless(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  const MeshlessDesign design = load_meshless_design(root, options, "run", log);
  const MeshlessScene& S = *design.scene;
  const MeshlessInverse* inverse = design.inverse.get();
  StaticFunctional& f = *inverse->functional;
  OptimizerOptions optimizer = S.spec.inverse->optimizer;
  optimizer.progress = options.progress;
  const double initial = f.value(inverse->z0);
  const OptimizerResult result = minimize(f, inverse->z0, Bounds{}, {}, optimizer);
  const double final_value = f.value(result.z);
  const std::filesystem::path dir(options.out_dir);
  std::filesystem::create_directories(dir);
  MeshlessRun out{result.converged() || result.status == OptimizerStatus::max_iterations, to_string(result.status),
                  result.z, meshless_fields(S, meshless_node_values(S), f.state(), f.parameters())};
  write_meshless_fields(out.fields, S, dir);
  nlohmann::ordered_json report;
  report["status"] = to_string(result.status);
  report["message"] = result.message;
  report["scene"] = S.spec.name;
  report["discretization"] = meshless_discretization_json(S);
  report["backend"] = to_string(optimizer.backend);
  report["objective_initial"] = initial;
  report["objective"] = final_value;
  report["iterations"] = result.history.size();
  report["seconds"] = result.seconds;
  report["z"] = to_json(result.z);
  report["labels"] = inverse->labels;
  report["history"] = optimizer_history_json(result);
  const std::string path = write_report(options.out_dir, report);
  if (log)
    *log << "status " << to_string(result.status) << " after " << result.history.size() << " iterations: J " << initial << " -> "
         << final_value << "\nwrote " << path << ", nodes.vtu and samples.vtu\n";
  return out;
}

bool run_meshless_scene(const SceneNode& root, const MeshlessVerbOptions& options, std::ostream* log) {
  return run_meshless(root, options, log).succeeded;
}

}  // namespace tailor
