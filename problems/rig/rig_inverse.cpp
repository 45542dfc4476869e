#include "problems/rig/rig_inverse.hpp"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "problems/optimizer_report.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_error.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {

std::vector<int> arm_material_regions(const Mesh& mesh, const TwoBoneArmOptions& arm) {
  std::vector<int> regions(static_cast<std::size_t>(mesh.num_elements()), 0);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    double x = 0.0;
    for (int a = 0; a < 4; ++a) x += mesh.rest_positions(mesh.elements(e, a), 0) / 4.0;
    regions[static_cast<std::size_t>(e)] = mesh.element_regions[e] == 1 ? 1 : x > 0.5 * arm.length ? 2 : 0;
  }
  return regions;
}

namespace {

// The moduli per element for per-region factors of the scene's moduli.
Vector scaled_moduli(const Vector& moduli, const std::vector<int>& regions, const Eigen::Vector3d& scale) {
  Vector e = moduli;
  for (int k = 0; k < e.size(); ++k) e[k] *= scale[regions[static_cast<std::size_t>(k)]];
  return e;
}

}  // namespace

std::unique_ptr<RigMarkerInverse> rig_marker_inverse(const RigSceneSpec& spec, int steps,
                                                     const Eigen::Vector3d& target_scale) {
  if (spec.reduced)
    throw SceneError(spec.name + ": the inverse use differentiates the full-space dynamics; remove \"reduction\"");
  auto inv = std::make_unique<RigMarkerInverse>();
  inv->arm = two_bone_arm(spec.arm);
  RiggedBody& body = inv->arm.body;
  body.gravity = spec.gravity;
  const Mesh& mesh = body.mesh;
  inv->rig = std::make_unique<Rig>(spec.bones, mesh.rest_positions, spec.weights, spec.corrections);
  inv->trajectory = std::make_unique<PoseTrajectory>(spec.key_times, spec.key_poses);
  (mesh.rest_positions.rowwise() - spec.marker.transpose()).rowwise().squaredNorm().minCoeff(&inv->marker);
  inv->regions = arm_material_regions(mesh, spec.arm);
  inv->steps = steps > 0 ? steps : static_cast<int>(std::lround(spec.duration / spec.dynamics.time_step));
  inv->model = moving_rest_model(*inv->rig, *inv->trajectory, body, spec.dynamics);

  TimeIntegratorOptions integrator;
  integrator.scheme = TimeScheme::implicit_euler;
  integrator.time_step = spec.dynamics.time_step;
  integrator.newton.relative_tolerance = std::min(spec.dynamics.newton_tolerance, 1e-10);
  integrator.newton.max_iterations = std::max(spec.dynamics.max_newton_iterations, 40);
  inv->integrator = std::make_unique<TimeIntegrator>(*inv->model.model, integrator);

  // The measured motion: the forward pass at the scaled moduli.
  const int n = 3 * mesh.num_vertices();
  Vector p_target = inv->model.parameters;
  p_target.segment(inv->model.youngs_offset, mesh.num_elements()) =
      scaled_moduli(body.youngs_modulus, inv->regions, target_scale);
  DynamicState state = inv->integrator->initial_state(Vector::Zero(n), Vector::Zero(n), p_target);
  inv->target.resize(inv->steps, 3);
  for (int k = 1; k <= inv->steps; ++k) {
    const NewtonResult r = inv->integrator->step(state, p_target);
    if (!r.converged())
      throw SceneError(spec.name + ": the measured motion's step " + std::to_string(k) + " failed: " + r.message);
    inv->target.row(k - 1) = state.x.segment<3>(3 * inv->marker).transpose();
  }
  // Relative to the measured jiggle: J = 1/2 sum_n |x_m - y_n|^2 / sum_n |y_n - X_m|^2.
  const double measured = inv->target.squaredNorm();
  if (!(measured > 0.0)) throw SceneError(spec.name + ": the marker does not move relative to the rig");
  std::vector<Keyframe> frames;
  for (int k = 1; k <= inv->steps; ++k) frames.push_back({k, inv->target.row(k - 1), 1.0 / measured});
  auto objective =
      std::make_shared<KeyframeTargets>(3, std::vector<int>{inv->marker}, TrajectoryQuantity::position, frames);

  // z = log E per region into P.
  const int ne = mesh.num_elements();
  auto moduli = compose(region_scatter_map(inv->regions, kArmRegions), exp_map(kArmRegions));
  ParameterizationPtr map = embed_blocks(inv->model.parameters, {{inv->model.youngs_offset, moduli}});
  inv->z0.resize(kArmRegions);
  for (int r = 0; r < kArmRegions; ++r) {
    int e = 0;
    while (e < ne && inv->regions[static_cast<std::size_t>(e)] != r) ++e;
    if (e == ne) throw SceneError(spec.name + ": the arm has no element in material region " + std::to_string(r));
    inv->z0[r] = std::log(body.youngs_modulus[e]);
  }
  TransientFunctionalOptions options;
  options.steps = inv->steps;
  inv->functional = std::make_unique<TransientFunctional>(*inv->integrator, map, objective, Vector::Zero(n),
                                                          Vector::Zero(n), options);
  return inv;
}

TaylorTestResult gradcheck_rig_scene(const RigSceneSpec& spec, const std::string& out_dir, unsigned seed,
                                     std::ostream* log) {
  const Eigen::Vector3d target_scale = spec.inverse.target_scale;
  const std::unique_ptr<RigMarkerInverse> inv = rig_marker_inverse(spec, spec.inverse.steps, target_scale);
  TaylorTestOptions taylor;
  taylor.seed = seed;
  const TaylorTestResult result = taylor_test(*inv->functional, inv->z0, taylor);
  if (log)
    *log << "gradient of 1/2 sum_n |x_marker(t_n) - y_n|^2 / sum_n |y_n - X_marker(t_n)|^2 (y: the marker at moduli x (" << target_scale.transpose()
         << ")) with respect to log E of the upper arm, belly and forearm, over " << inv->steps << " steps\n"
         << result.table();
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json document = taylor_json(result);
  add_report_header(document);
  document["kind"] = "rig_dynamics";
  document["scene"] = {{"name", spec.name}};
  document["problem"] = {{"design", "log youngs_modulus of upper_arm, belly, forearm"},
                         {"objective", "1/2 sum_n |x_marker(t_n) - y_n|^2 / sum_n |y_n - X_marker(t_n)|^2"},
                         {"target_scale", {target_scale[0], target_scale[1], target_scale[2]}},
                         {"marker_vertex", inv->marker},
                         {"steps", inv->steps},
                         {"elements", inv->arm.body.mesh.num_elements()}};
  write_report_file((std::filesystem::path(out_dir) / "gradcheck.json").string(), document);
  return result;
}

}  // namespace tailor

namespace tailor {

RigInverseRun run_rig_inverse(const RigSceneSpec& spec, const std::string& out_dir, std::ostream* log) {
  if (!spec.has_inverse) throw SceneError(spec.name + ": `run` needs an \"inverse\" section in rig_dynamics");
  const std::unique_ptr<RigMarkerInverse> inv = rig_marker_inverse(spec, spec.inverse.steps, spec.inverse.target_scale);
  RigInverseRun run;
  run.expected = inv->z0 + spec.inverse.target_scale.array().log().matrix();
  if (log)
    *log << "recovering log E per region (upper arm, belly, forearm) from the marker's motion over " << inv->steps
         << " steps; expected " << run.expected.transpose() << "\n";
  run.result = minimize(*inv->functional, inv->z0, Bounds{}, {}, spec.inverse.optimizer);
  run.moduli_error = 0.0;
  for (int r = 0; r < kArmRegions; ++r)
    run.moduli_error = std::max(run.moduli_error, std::abs(std::exp(run.result.z[r] - run.expected[r]) - 1.0));
  if (log)
    *log << run.result.report() << "\nrecovered log E " << run.result.z.transpose() << ", largest relative modulus error "
         << run.moduli_error << "\n";
  nlohmann::ordered_json report;
  add_report_header(report);
  report["kind"] = "rig_dynamics";
  report["scene"] = {{"name", spec.name}};
  auto list = [](const Vector& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  report["inverse"] = {{"design", "log youngs_modulus of upper_arm, belly, forearm"},
                       {"objective", "1/2 sum_n |x_marker(t_n) - y_n|^2 / sum_n |y_n - X_marker(t_n)|^2"},
                       {"steps", inv->steps},
                       {"marker_vertex", inv->marker},
                       {"target_scale", list(spec.inverse.target_scale)},
                       {"initial", list(inv->z0)},
                       {"expected", list(run.expected)},
                       {"recovered", list(run.result.z)},
                       {"largest_relative_modulus_error", run.moduli_error},
                       {"objective_value", run.result.objective},
                       {"status", run.result.converged() ? "converged" : "not converged"},
                       {"message", run.result.message}};
  report["optimizer"] = optimizer_history_json(run.result);
  write_report(out_dir, report);
  return run;
}

}  // namespace tailor
