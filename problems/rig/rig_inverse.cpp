#include "problems/rig/rig_inverse.hpp"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

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
  std::vector<Keyframe> frames;
  inv->target.resize(inv->steps, 3);
  const double weight = spec.dynamics.time_step;
  for (int k = 1; k <= inv->steps; ++k) {
    const NewtonResult r = inv->integrator->step(state, p_target);
    if (!r.converged())
      throw SceneError(spec.name + ": the measured motion's step " + std::to_string(k) + " failed: " + r.message);
    inv->target.row(k - 1) = state.x.segment<3>(3 * inv->marker).transpose();
    frames.push_back({k, inv->target.row(k - 1), weight});
  }
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
  const Eigen::Vector3d target_scale(1.3, 0.7, 1.2);
  const std::unique_ptr<RigMarkerInverse> inv = rig_marker_inverse(spec, 0, target_scale);
  TaylorTestOptions taylor;
  taylor.seed = seed;
  const TaylorTestResult result = taylor_test(*inv->functional, inv->z0, taylor);
  if (log)
    *log << "gradient of h/2 sum_n |x_marker(t_n) - y_n|^2 (y: the marker at moduli x (1.3, 0.7, 1.2)) with respect "
            "to log E of the upper arm, belly and forearm, over "
         << inv->steps << " steps\n"
         << result.table();
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json document = taylor_json(result);
  add_report_header(document);
  document["kind"] = "rig_dynamics";
  document["scene"] = {{"name", spec.name}};
  document["problem"] = {{"design", "log youngs_modulus of upper_arm, belly, forearm"},
                         {"objective", "h/2 sum_n |x_marker(t_n) - y_n|^2"},
                         {"target_scale", {target_scale[0], target_scale[1], target_scale[2]}},
                         {"marker_vertex", inv->marker},
                         {"steps", inv->steps},
                         {"elements", inv->arm.body.mesh.num_elements()}};
  write_report_file((std::filesystem::path(out_dir) / "gradcheck.json").string(), document);
  return result;
}

}  // namespace tailor
