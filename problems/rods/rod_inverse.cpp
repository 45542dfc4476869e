#include "problems/rods/rod_inverse.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "adjoint/parameterization.hpp"
#include "objectives/target_dofs.hpp"
#include "objectives/tikhonov.hpp"
#include "objectives/weighted_sum.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/optimizer_report.hpp"
#include "problems/optimizer_section.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_node.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {

std::string to_string(RodDesignBlock block) {
  switch (block) {
    case RodDesignBlock::rest_curvature:
      return "rest_curvature";
    case RodDesignBlock::rest_twist:
      return "rest_twist";
    case RodDesignBlock::rest_length:
      return "rest_length";
    case RodDesignBlock::radius:
      return "radius";
    case RodDesignBlock::youngs_modulus:
      return "youngs_modulus";
  }
  return "?";
}

std::string to_string(RodInverseMethod method) {
  switch (method) {
    case RodInverseMethod::automatic:
      return "auto";
    case RodInverseMethod::inverse_statics:
      return "inverse_statics";
    case RodInverseMethod::optimizer:
      return "optimizer";
  }
  return "?";
}

namespace {

bool is_logarithmic(RodDesignBlock b) {
  return b == RodDesignBlock::rest_length || b == RodDesignBlock::radius ||
         b == RodDesignBlock::youngs_modulus;
}

RodDesignBlock parse_block(const SceneNode& node) {
  const std::string s =
      node.choice({"rest_curvature", "rest_twist", "rest_length", "radius", "youngs_modulus"});
  for (RodDesignBlock b :
       {RodDesignBlock::rest_curvature, RodDesignBlock::rest_twist, RodDesignBlock::rest_length,
        RodDesignBlock::radius, RodDesignBlock::youngs_modulus})
    if (to_string(b) == s) return b;
  node.fail("unknown design block");
}

}  // namespace

std::pair<int, int> rod_design_block_range(const RodSceneModel& m, int k, RodDesignBlock b) {
  const RodParameterBlocks& blocks = m.blocks[static_cast<std::size_t>(k)];
  const DiscreteRod& rod = *m.rods[static_cast<std::size_t>(k)];
  switch (b) {
    case RodDesignBlock::rest_curvature:
      return {blocks.rest_curvature, 2 * rod.num_interior()};
    case RodDesignBlock::rest_twist:
      return {blocks.rest_twist, rod.num_interior()};
    case RodDesignBlock::rest_length:
      return {blocks.rest_length, rod.num_edges()};
    case RodDesignBlock::radius:
      return {blocks.radius, rod.num_edges()};
    case RodDesignBlock::youngs_modulus:
      return {blocks.youngs_modulus, rod.num_edges()};
  }
  return {0, 0};
}

RodInverseSpec parse_rod_inverse(const SceneNode& root, const RodSceneSpec& scene) {
  const SceneNode inv = root.at("inverse");
  inv.expect_keys({"rod", "design", "per", "target", "regularization", "method", "optimizer", "gradcheck"});
  RodInverseSpec spec;
  if (const auto rod = inv.find("rod")) {
    if (rod->is_string()) {
      const std::string name = rod->string();
      const auto it = std::find_if(scene.rods.begin(), scene.rods.end(),
                                   [&](const RodSpec& r) { return r.name == name; });
      if (it == scene.rods.end()) rod->fail("no rod named '" + name + "'");
      spec.rod = static_cast<int>(it - scene.rods.begin());
    } else {
      spec.rod = rod->integer(0);
      if (spec.rod >= static_cast<int>(scene.rods.size()))
        rod->fail("rod index out of range (the scene has " + std::to_string(scene.rods.size()) + ")");
    }
  }
  const SceneNode design = inv.at("design");
  if (design.is_string()) {
    spec.design.push_back(parse_block(design));
  } else {
    for (const SceneNode& b : design.items()) spec.design.push_back(parse_block(b));
    if (spec.design.empty()) design.fail("expected at least one block");
  }
  for (std::size_t i = 0; i < spec.design.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (spec.design[i] == spec.design[j])
        design.fail("block '" + to_string(spec.design[i]) + "' given twice");
  if (const auto per = inv.find("per")) spec.per_rod = per->choice({"edge", "rod"}) == "rod";

  const RodSpec& rod = scene.rods[static_cast<std::size_t>(spec.rod)];
  const int nv = static_cast<int>(rod.points.rows());
  const auto target = inv.find("target");
  if (!target || (target->is_string() && target->choice({"drawn"}) == "drawn")) {
    for (int v = 0; v < nv; ++v) spec.target_vertices.push_back(v);
    spec.target_positions = rod.points;
  } else {
    target->expect_keys({"vertices", "positions", "displacements", "components"});
    if (const auto comps = target->find("components")) {
      spec.components = comps->integers(0);
      if (spec.components.empty()) comps->fail("expected at least one of 0, 1, 2");
      for (std::size_t i = 0; i < spec.components.size(); ++i) {
        if (spec.components[i] > 2) comps->fail("components are 0, 1, 2 (x, y, z)");
        for (std::size_t j = 0; j < i; ++j)
          if (spec.components[i] == spec.components[j]) comps->fail("a component given twice");
      }
    }
    spec.target_vertices = target->at("vertices").integers(0);
    for (int v : spec.target_vertices)
      if (v >= nv)
        target->at("vertices")
            .fail("vertex " + std::to_string(v) + " out of range (the rod has " + std::to_string(nv) + ")");
    if (spec.target_vertices.empty()) target->at("vertices").fail("expected at least one vertex");
    const bool displacements = target->has("displacements");
    if (displacements == target->has("positions"))
      target->fail("needs exactly one of 'positions', 'displacements'");
    const SceneNode rows = target->at(displacements ? "displacements" : "positions");
    const std::vector<SceneNode> items = rows.items();
    if (items.size() != spec.target_vertices.size()) rows.fail("expected one row per vertex");
    spec.target_positions.resize(static_cast<Eigen::Index>(items.size()), 3);
    for (std::size_t i = 0; i < items.size(); ++i) {
      Eigen::Vector3d t = items[i].vector(3);
      if (displacements) t += rod.points.row(spec.target_vertices[i]).transpose();
      spec.target_positions.row(static_cast<Eigen::Index>(i)) = t.transpose();
    }
  }
  if (inv.has("regularization")) spec.regularization = inv.at("regularization").non_negative();
  if (const auto method = inv.find("method")) {
    const std::string m = method->choice({"auto", "inverse_statics", "optimizer"});
    spec.method = m == "auto"              ? RodInverseMethod::automatic
                  : m == "inverse_statics" ? RodInverseMethod::inverse_statics
                                           : RodInverseMethod::optimizer;
    if (spec.method == RodInverseMethod::inverse_statics)
      if (const std::string why = rod_inverse_statics_obstacle(spec, scene); !why.empty())
        method->fail("inverse statics does not apply: " + why);
  }

  spec.optimizer.backend = OptimizerBackend::ceres_least_squares;
  spec.optimizer.max_iterations = 100;
  spec.optimizer.gradient_tolerance = 1e-14;
  spec.optimizer.objective_tolerance = 0.0;
  if (const auto opt = inv.find("optimizer"))
    spec.optimizer = parse_optimizer_section(*opt, spec.optimizer, {"a rod scene", true, false, {}});
  if (const auto g = inv.find("gradcheck")) {
    g->expect_keys({"seed"});
    if (g->has("seed")) spec.seed = static_cast<unsigned>(g->at("seed").integer(0));
  }
  return spec;
}

double RodInverseProblem::shape_error(const Vector& x) const {
  const int first = model.first_vertex[static_cast<std::size_t>(spec.rod)];
  double e = 0.0;
  for (std::size_t i = 0; i < spec.target_vertices.size(); ++i) {
    const int g = first + spec.target_vertices[i];
    double d2 = 0.0;
    for (int c : spec.components)
      d2 += std::pow(x[3 * g + c] - spec.target_positions(static_cast<Eigen::Index>(i), c), 2);
    e = std::max(e, std::sqrt(d2));
  }
  return e / length;
}

std::unique_ptr<RodInverseProblem> build_rod_inverse(const nlohmann::json& document,
                                                     const std::string& source, const std::string& name) {
  return build_rod_inverse(SceneNode(document, source, ""), name);
}

std::unique_ptr<RodInverseProblem> build_rod_inverse(const SceneNode& root, const std::string& name) {
  auto problem = std::make_unique<RodInverseProblem>();
  RodInverseProblem& P = *problem;
  P.name = name;
  P.source = root.source();
  P.scene = parse_rod_scene(root);
  if (!root.has("inverse")) root.fail("needs an \"inverse\" section for gradcheck and run (docs/rods.md)");
  P.spec = parse_rod_inverse(root, P.scene);
  P.model = build_rod_model(P.scene);
  const int k = P.spec.rod;
  const DiscreteRod& rod = *P.model.rods[static_cast<std::size_t>(k)];
  const Eigen::MatrixX3d& drawn = P.scene.rods[static_cast<std::size_t>(k)].points;
  for (int j = 0; j + 1 < drawn.rows(); ++j) P.length += (drawn.row(j + 1) - drawn.row(j)).norm();

  std::vector<ParameterBlock> blocks;
  std::vector<ObjectivePtr> parts;
  std::vector<double> coefficients;
  std::vector<Vector> z_parts;
  for (RodDesignBlock b : P.spec.design) {
    const auto [offset, size] = rod_design_block_range(P.model, k, b);
    const Vector initial = P.model.p.segment(offset, size);
    const std::string label = to_string(b);
    if (is_logarithmic(b)) {
      // q = q0 exp(z) per entry, or per rod q = q0 exp(z_rod).
      ParameterizationPtr map = compose(scale_map(initial), exp_map(size));
      if (P.spec.per_rod) {
        map = compose(map, region_scatter_map(std::vector<int>(static_cast<std::size_t>(size), 0), 1));
        P.labels.push_back(label);
        z_parts.push_back(Vector::Zero(1));
      } else {
        for (int j = 0; j < size; ++j) P.labels.push_back(label + "[" + std::to_string(j) + "]");
        z_parts.push_back(Vector::Zero(size));
      }
      blocks.push_back({offset, map});
    } else {
      blocks.push_back({offset, identity_map(size)});
      z_parts.push_back(initial);
      if (b == RodDesignBlock::rest_curvature)
        for (int i = 0; i < rod.num_interior(); ++i)
          for (int a = 0; a < 2; ++a)
            P.labels.push_back(label + "[" + std::to_string(i + 1) + "][" + std::to_string(a + 1) + "]");
      else
        for (int i = 0; i < size; ++i) P.labels.push_back(label + "[" + std::to_string(i + 1) + "]");
    }
    if (P.spec.regularization > 0.0) {
      // Relative change for the positive blocks; curvatures and twists are angles already.
      Vector weights = is_logarithmic(b) ? Vector(initial.cwiseInverse()) : Vector::Ones(size);
      parts.push_back(std::make_shared<Tikhonov>(offset, size, P.spec.regularization, initial, weights));
      coefficients.push_back(1.0);
    }
  }
  int nz = 0;
  for (const Vector& z : z_parts) nz += static_cast<int>(z.size());
  P.z0.resize(nz);
  nz = 0;
  for (const Vector& z : z_parts) P.z0.segment(nz, z.size()) = z, nz += static_cast<int>(z.size());
  P.parameterization = embed_blocks(P.model.p, blocks);

  // 1/2 sum |x_v - t_v|^2 / (m L^2): the misfit relative to the rod's length, m targets.
  std::vector<int> dofs;
  std::vector<double> targets;
  for (std::size_t i = 0; i < P.spec.target_vertices.size(); ++i)
    for (int c : P.spec.components) {
      dofs.push_back(rod.position_dof(P.spec.target_vertices[i], c));
      targets.push_back(P.spec.target_positions(static_cast<Eigen::Index>(i), c));
    }
  const double w = 1.0 / (static_cast<double>(P.spec.target_vertices.size()) * P.length * P.length);
  parts.insert(
      parts.begin(),
      std::make_shared<TargetDofs>(
          dofs, Eigen::Map<const Vector>(targets.data(), static_cast<Eigen::Index>(targets.size())), w));
  coefficients.insert(coefficients.begin(), 1.0);
  P.objective = parts.size() == 1 ? parts[0] : std::make_shared<WeightedSum>(parts, coefficients);

  StaticFunctionalOptions options;
  options.newton.max_iterations = P.scene.max_newton_iterations;
  // Convergence against the loads: in a rest-shape design the drawn (rest) state is nearly the
  // equilibrium near the optimum, so the residual there, which a warm start's relative tolerance
  // refers to, becomes tiny and the relative tolerance unreachable in double precision.
  options.newton.absolute_tolerance = options.newton.relative_tolerance * P.model.load->forces().norm();
  P.functional =
      std::make_unique<StaticFunctional>(*P.model.model, P.parameterization, P.objective,
                                         P.model.model->elimination().restrict_state(P.model.rest), options);
  return problem;
}

namespace {

nlohmann::ordered_json scene_json(const RodInverseProblem& P) {
  nlohmann::ordered_json design = nlohmann::ordered_json::array();
  for (RodDesignBlock b : P.spec.design) design.push_back(to_string(b));
  return {{"name", P.name},
          {"source", P.source},
          {"rod", P.scene.rods[static_cast<std::size_t>(P.spec.rod)].name},
          {"design", design},
          {"per", P.spec.per_rod ? "rod" : "edge"},
          {"design_size", P.z0.size()},
          {"target_vertices", P.spec.target_vertices.size()}};
}

}  // namespace

RodGradcheck gradcheck_rod_scene(const RodInverseProblem& problem, const std::string& out_dir,
                                 std::optional<unsigned> seed, bool hessian, std::ostream* log) {
  TaylorTestOptions options;
  options.seed = seed.value_or(problem.spec.seed);
  RodGradcheck check;
  check.gradient = taylor_test(*problem.functional, problem.z0, options);
  if (log)
    *log << "gradient of the rod shape misfit with respect to " << problem.z0.size() << " design variables ("
         << dump_json(scene_json(problem)["design"]) << ")\n"
         << check.gradient.table();
  if (hessian) {
    check.hessian = taylor_test_hessian(*problem.functional, problem.z0, options);
    if (log) *log << "Hessian-vector products:\n" << check.hessian->table();
  }
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json document = taylor_json(check.gradient);
  add_report_header(document);
  document["scene"] = scene_json(problem);
  document["seed"] = options.seed;
  if (check.hessian) document["hessian"] = taylor_json(*check.hessian);
  write_report_file((std::filesystem::path(out_dir) / "gradcheck.json").string(), document);
  return check;
}

namespace {

nlohmann::ordered_json stability_json(const RodStability& s) {
  return {{"stable", s.stable()},
          {"smallest_pivot", s.smallest_pivot},
          {"largest_pivot", s.largest_pivot},
          {"nonpositive_pivots", s.nonpositive_pivots},
          {"residual_floor", s.residual_floor}};
}

}  // namespace

RodInverseRun run_rod_inverse(RodInverseProblem& P, const std::string& out_dir, std::ostream* log,
                              std::ostream* progress) {
  RodInverseRun run;
  StaticFunctional& f = *P.functional;
  std::filesystem::create_directories(out_dir);
  const std::filesystem::path dir(out_dir);
  OptimizerOptions options = P.spec.optimizer;
  options.progress = progress;
  const std::string obstacle = P.spec.method == RodInverseMethod::optimizer
                                   ? std::string("the scene asks for the optimizer")
                                   : rod_inverse_statics_obstacle(P.spec, P.scene);
  if (log)
    *log << "designing " << P.name << ": " << P.z0.size() << " variables "
         << dump_json(scene_json(P)["design"]) << ", " << P.spec.target_vertices.size() << " target vertices, "
         << (obstacle.empty() ? std::string("inverse statics") : "optimizer " + to_string(options.backend) +
                                                                     " (inverse statics: " + obstacle + ")")
         << "\n";

  // The shape at z0, for the report: solved first on the optimizer's path (its first
  // evaluation), last on inverse statics' (whose equilibrium Newton then finds at once from the
  // drawn state, where the functional's first solve starts).
  double initial_objective = 0.0;
  auto solve_initial = [&] {
    initial_objective = f.value(P.z0);
    run.initial_shape_error = P.shape_error(f.state());
    write_rods_vtu((dir / "rods_initial.vtu").string(), P.model.outputs(), f.state(), f.parameters());
  };
  Vector start = P.z0;
  bool optimize = true;
  if (!obstacle.empty()) {
    solve_initial();
  } else {
    run.statics = solve_rod_inverse_statics(P);
    const RodInverseStaticsResult& s = *run.statics;
    if (log) *log << "inverse statics (" << s.seconds << " s): " << s.message << "\n";
    if (s.accepted() || P.spec.method == RodInverseMethod::inverse_statics) {
      optimize = false;
      run.method = RodInverseMethod::inverse_statics;
      run.result.z = s.z;
      run.result.seconds = s.seconds;
      run.result.status = s.accepted() ? OptimizerStatus::converged : OptimizerStatus::failed;
      run.result.message = "inverse statics: " + s.message;
    } else {
      run.fallback = "inverse statics rejected: " + s.message;
      start = s.z;
      if (log) *log << "falling back to the optimizer from its result\n";
    }
  }
  if (optimize) {
    run.method = RodInverseMethod::optimizer;
    run.result = minimize(f, start, Bounds{}, {}, options);
    if (run.statics) run.result.seconds += run.statics->seconds;
  }
  double final_objective = run.result.objective;
  try {
    final_objective = f.value(run.result.z);
    run.final_converged = f.last_newton().converged();
  } catch (const EvaluationError&) {
    run.final_converged = false;
  }
  if (!optimize) run.result.objective = final_objective;
  run.shape_error = P.shape_error(f.state());
  run.final_stability =
      rod_stability(*P.model.model, P.model.model->elimination().restrict_state(f.state()), f.parameters());
  write_rods_vtu((dir / "rods.vtu").string(), P.model.outputs(), f.state(), f.parameters());
  const Vector final_parameters = f.parameters();
  if (obstacle.empty()) solve_initial();

  nlohmann::ordered_json report;
  add_report_header(report);
  report["status"] = to_string(run.result.status);
  report["message"] = run.result.message;
  report["scene"] = scene_json(P);
  report["method_requested"] = to_string(P.spec.method);
  report["method"] = to_string(run.method);
  report["fallback"] = run.fallback.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(run.fallback);
  if (run.statics) {
    const RodInverseStaticsResult& s = *run.statics;
    report["inverse_statics"] = {{"accepted", s.accepted()},
                                 {"message", s.message},
                                 {"steps", s.steps},
                                 {"residual_initial", s.residual_initial},
                                 {"residual", s.residual},
                                 {"residuals", s.residuals},
                                 {"at_round_off", s.at_round_off},
                                 {"stability", stability_json(s.stability)},
                                 {"seconds", s.seconds}};
  } else {
    report["inverse_statics"] = {{"not_applicable", obstacle}};
  }
  report["final_stability"] = stability_json(run.final_stability);
  report["backend"] = to_string(options.backend);
  report["objective_initial"] = initial_objective;
  report["objective"] = final_objective;
  report["shape_error_initial"] = run.initial_shape_error;
  report["shape_error"] = run.shape_error;
  report["equilibrium_converged"] = run.final_converged;
  report["iterations"] = run.result.history.size();
  report["seconds"] = run.result.seconds;
  nlohmann::ordered_json design = nlohmann::ordered_json::object();
  for (RodDesignBlock b : P.spec.design) {
    const auto [offset, size] = rod_design_block_range(P.model, P.spec.rod, b);
    const Vector q = final_parameters.segment(offset, size);
    design[to_string(b)] = std::vector<double>(q.data(), q.data() + q.size());
  }
  report["design"] = design;
  report["z"] = std::vector<double>(run.result.z.data(), run.result.z.data() + run.result.z.size());
  report["labels"] = P.labels;
  const FunctionalCounters& c = f.counters();
  report["timings"] = {{"evaluations", c.evaluations},
                       {"forward_solves", c.forward_solves},
                       {"adjoint_solves", c.adjoint_solves},
                       {"forward_seconds", c.forward_seconds},
                       {"adjoint_seconds", c.adjoint_seconds}};
  report["history"] = optimizer_history_json(run.result);
  run.report_path = write_report(out_dir, report);
  if (log)
    *log << "method " << to_string(run.method) << ", status " << to_string(run.result.status) << " after "
         << run.result.history.size()
         << " iterations (" << run.result.seconds << " s): shape error " << run.initial_shape_error << " -> "
         << run.shape_error << " of the rod's length, J " << initial_objective << " -> " << final_objective
         << "\nwrote " << run.report_path << ", " << (dir / "rods.vtu").string() << " and rods_initial.vtu\n";
  return run;
}

}  // namespace tailor
