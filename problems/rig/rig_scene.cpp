#include "problems/rig/rig_scene.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "forward/core/atomic_file.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/optimizer_section.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

// The rig: bones (name, parent name or null, joint, dofs) and per-vertex weights (rows of
// bone weights, one per mesh vertex), optional corrections (pose, per-vertex displacement).
void parse_rig(const SceneNode& rig, RigSceneSpec& spec, int vertices) {
  rig.expect_keys({"bones", "weights", "corrections"});
  std::vector<std::string> names;
  for (const SceneNode& b : rig.at("bones").items()) {
    b.expect_keys({"name", "parent", "joint", "dofs"});
    Bone bone;
    bone.name = b.at("name").string();
    if (const auto parent = b.find("parent"); parent && !parent->json().is_null()) {
      const std::string p = parent->string();
      const auto it = std::find(names.begin(), names.end(), p);
      if (it == names.end()) parent->fail("no earlier bone is named \"" + p + "\"");
      bone.parent = static_cast<int>(it - names.begin());
    }
    if (b.has("joint")) bone.joint = b.at("joint").vector(3);
    if (b.has("dofs"))
      for (const SceneNode& d : b.at("dofs").items()) {
        d.expect_keys({"rotation", "translation"});
        const std::string type = d.only_key({"rotation", "translation"});
        const Eigen::Vector3d axis = d.at(type.c_str()).vector(3);
        if (axis.norm() == 0.0) d.at(type.c_str()).fail("the axis must not be zero");
        bone.dofs.push_back({type == "rotation" ? BoneDofType::rotation : BoneDofType::translation, axis.normalized()});
      }
    names.push_back(bone.name);
    spec.bones.push_back(bone);
  }
  if (spec.bones.empty()) rig.at("bones").fail("needs at least one bone");
  const SceneNode weights = rig.at("weights");
  const std::vector<SceneNode> rows = weights.items();
  if (static_cast<int>(rows.size()) != vertices)
    weights.fail("needs one row per mesh vertex (" + std::to_string(vertices) + "), got " + std::to_string(rows.size()));
  spec.weights.resize(vertices, static_cast<int>(spec.bones.size()));
  for (int v = 0; v < vertices; ++v) {
    const SceneNode& row = rows[static_cast<std::size_t>(v)];
    const Eigen::VectorXd w = row.vector(static_cast<int>(spec.bones.size()));
    if (w.minCoeff() < 0.0 || std::abs(w.sum() - 1.0) > 1e-9) row.fail("weights must be >= 0 and sum to 1");
    spec.weights.row(v) = w.transpose();
  }
  int parameters = 0;
  for (const Bone& b : spec.bones) parameters += static_cast<int>(b.dofs.size());
  if (const auto corrections = rig.find("corrections"))
    for (const SceneNode& c : corrections->items()) {
      c.expect_keys({"pose", "displacements"});
      PoseCorrection correction;
      correction.pose = c.at("pose").vector(parameters);
      const std::vector<SceneNode> d = c.at("displacements").items();
      if (static_cast<int>(d.size()) != vertices) c.at("displacements").fail("needs one row per mesh vertex");
      correction.displacement.resize(vertices, 3);
      for (int v = 0; v < vertices; ++v) correction.displacement.row(v) = d[static_cast<std::size_t>(v)].vector(3).transpose();
      spec.corrections.push_back(correction);
    }
}

int num_parameters(const RigSceneSpec& spec) {
  int p = 0;
  for (const Bone& b : spec.bones) p += static_cast<int>(b.dofs.size());
  return p;
}

}  // namespace

RigSceneSpec parse_rig_scene(const SceneNode& root, const std::string& directory) {
  root.expect_keys({"name", "rig_dynamics"});
  RigSceneSpec spec;
  const SceneNode s = root.at("rig_dynamics");
  s.expect_keys({"arm", "material", "rig", "keyframes", "time_step", "duration", "rayleigh_mass", "gravity",
                 "newton_iterations", "output_every", "marker", "reduction", "inverse"});
  if (const auto arm = s.find("arm")) {
    arm->expect_keys({"length", "half_width", "cells_along", "cells_across", "blend"});
    if (arm->has("length")) spec.arm.length = arm->at("length").positive();
    if (arm->has("half_width")) spec.arm.half_width = arm->at("half_width").positive();
    if (arm->has("cells_along")) spec.arm.cells_along = arm->at("cells_along").integer(2);
    if (arm->has("cells_across")) spec.arm.cells_across = arm->at("cells_across").integer(1);
    if (arm->has("blend")) spec.arm.blend = arm->at("blend").positive();
  }
  if (const auto m = s.find("material")) {
    m->expect_keys({"model", "youngs_modulus", "poisson_ratio", "density", "belly_softness"});
    if (m->has("model")) {
      try {
        spec.arm.material = parse_material_kind(m->at("model").string());
      } catch (const std::invalid_argument& e) {
        m->at("model").fail(e.what());
      }
    }
    if (m->has("youngs_modulus")) spec.arm.youngs_modulus = m->at("youngs_modulus").positive();
    if (m->has("poisson_ratio")) spec.arm.poisson_ratio = m->at("poisson_ratio").open_interval(-1.0, 0.5);
    if (m->has("density")) spec.arm.density = m->at("density").positive();
    if (m->has("belly_softness")) spec.arm.belly_softness = m->at("belly_softness").positive();
  }
  const int vertices = (spec.arm.cells_along + 1) * (spec.arm.cells_across + 1) * (spec.arm.cells_across + 1);
  const SceneNode rig = s.at("rig");
  if (rig.is_string()) {
    std::filesystem::path path = rig.string();
    if (path.is_relative()) path = std::filesystem::path(directory) / path;
    const nlohmann::json document = read_scene_document(path.string());
    const std::string source = path.string();
    parse_rig(SceneNode(document, source, ""), spec, vertices);
  } else {
    parse_rig(rig, spec, vertices);
  }
  const int parameters = num_parameters(spec);
  for (const SceneNode& k : s.at("keyframes").items()) {
    k.expect_keys({"time", "pose"});
    spec.key_times.push_back(k.at("time").non_negative());
    spec.key_poses.push_back(k.at("pose").vector(parameters));
    if (spec.key_times.size() > 1 && !(spec.key_times.back() > spec.key_times[spec.key_times.size() - 2]))
      k.at("time").fail("keyframe times must increase");
  }
  if (spec.key_times.empty()) s.at("keyframes").fail("needs at least one keyframe");
  if (s.has("time_step")) spec.dynamics.time_step = s.at("time_step").positive();
  if (s.has("duration")) spec.duration = s.at("duration").positive();
  if (s.has("rayleigh_mass")) spec.dynamics.rayleigh_mass = s.at("rayleigh_mass").non_negative();
  if (s.has("gravity")) spec.gravity = s.at("gravity").vector(3);
  if (s.has("newton_iterations")) spec.dynamics.max_newton_iterations = s.at("newton_iterations").integer(1);
  if (s.has("output_every")) spec.output_every = s.at("output_every").integer(1);
  if (s.has("marker")) spec.marker = s.at("marker").vector(3);
  if (const auto r = s.find("reduction")) {
    r->expect_keys({"size", "linear_modes", "derivative_modes", "example_poses", "contact_distance",
                    "cubature_elements", "cubature_tolerance", "training_poses"});
    spec.reduced = true;
    PoseSpaceOptions& o = spec.reduction.options;
    if (r->has("size")) o.basis.size = r->at("size").integer(1);
    o.basis.linear_modes = std::min(o.basis.size, 10);
    if (r->has("linear_modes")) o.basis.linear_modes = r->at("linear_modes").integer(1);
    if (r->has("derivative_modes")) o.basis.derivative_modes = r->at("derivative_modes").integer(0);
    if (o.basis.derivative_modes > o.basis.linear_modes)
      r->fail("derivative_modes must not exceed linear_modes");
    for (const SceneNode& p : r->at("example_poses").items()) spec.reduction.example_poses.push_back(p.vector(parameters));
    if (spec.reduction.example_poses.empty()) r->at("example_poses").fail("needs at least one pose");
    if (r->has("contact_distance")) spec.reduction.contact_distance = r->at("contact_distance").non_negative();
    o.cubature.max_elements = 60;
    if (r->has("cubature_elements")) o.cubature.max_elements = r->at("cubature_elements").integer(1);
    if (r->has("cubature_tolerance")) o.cubature.tolerance = r->at("cubature_tolerance").positive();
    if (r->has("training_poses")) o.training_poses = r->at("training_poses").integer(1);
  }
  if (const auto inv = s.find("inverse")) {
    inv->expect_keys({"target_scale", "steps", "optimizer"});
    spec.has_inverse = true;
    if (inv->has("target_scale")) {
      spec.inverse.target_scale = inv->at("target_scale").vector(3);
      if (spec.inverse.target_scale.minCoeff() <= 0.0) inv->at("target_scale").fail("scale factors must be > 0");
    }
    if (inv->has("steps")) spec.inverse.steps = inv->at("steps").integer(1);
    spec.inverse.optimizer.max_iterations = 50;
    spec.inverse.optimizer.gradient_tolerance = 1e-12;
    if (const auto o = inv->find("optimizer"))
      spec.inverse.optimizer = parse_optimizer_section(*o, spec.inverse.optimizer, {"a rig_dynamics scene", false, false, {}});
    if (spec.reduced) inv->fail("the inverse use differentiates the full-space dynamics; remove \"reduction\"");
  }
  // The rig itself checks the hierarchy, axes, weights and corrections.
  try {
    const Mesh mesh = two_bone_arm(spec.arm).body.mesh;
    Rig(spec.bones, mesh.rest_positions, spec.weights, spec.corrections);
    PoseTrajectory(spec.key_times, spec.key_poses);
  } catch (const std::invalid_argument& e) {
    s.fail(e.what());
  }
  spec.name = root.has("name") ? root.at("name").string() : "rig_dynamics";
  return spec;
}

RigSceneRun run_rig_scene(const RigSceneSpec& spec, const std::string& out_dir, std::ostream* log) {
  RigSceneRun run;
  const auto start = std::chrono::steady_clock::now();
  TwoBoneArm arm = two_bone_arm(spec.arm);
  arm.body.gravity = spec.gravity;
  const Mesh& mesh = arm.body.mesh;
  const Rig rig(spec.bones, mesh.rest_positions, spec.weights, spec.corrections);
  const PoseTrajectory trajectory(spec.key_times, spec.key_poses);
  int marker = 0;
  (mesh.rest_positions.rowwise() - spec.marker.transpose()).rowwise().squaredNorm().minCoeff(&marker);

  nlohmann::ordered_json report;
  add_report_header(report);
  report["kind"] = "rig_dynamics";
  report["scene"] = {{"name", spec.name}};
  report["mesh"] = {{"vertices", mesh.num_vertices()}, {"elements", mesh.num_elements()},
                    {"fixed_vertices", arm.body.fixed_vertices.size()}};
  report["rig"] = {{"bones", spec.bones.size()}, {"parameters", rig.num_parameters()},
                   {"corrections", spec.corrections.size()}};

  std::unique_ptr<MovingRestDynamics> full;
  std::unique_ptr<PoseSpaceDynamics> reduced;
  if (spec.reduced) {
    Eigen::VectorXi owner;
    const Eigen::MatrixXi facets = boundary_facets(mesh, &owner);
    std::vector<int> surface(facets.data(), facets.data() + facets.size());
    std::sort(surface.begin(), surface.end());
    surface.erase(std::unique(surface.begin(), surface.end()), surface.end());
    std::vector<ExamplePose> examples;
    for (const Vector& pose : spec.reduction.example_poses) {
      ExamplePose e{pose, Matrix()};
      if (spec.reduction.contact_distance > 0.0)
        e.contact_constraints = contact_constraints_at(rig, pose, surface, spec.reduction.contact_distance);
      examples.push_back(e);
    }
    reduced = std::make_unique<PoseSpaceDynamics>(rig, arm.body, examples, spec.reduction.options, spec.dynamics);
    nlohmann::ordered_json poses = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < examples.size(); ++i) {
      const ExamplePosePrecomputation& p = reduced->precomputation()[i];
      poses.push_back({{"pose", std::vector<double>(examples[i].pose.data(), examples[i].pose.data() + examples[i].pose.size())},
                       {"contact_constraints", p.contact_constraints},
                       {"basis_seconds", p.basis_seconds},
                       {"cubature_seconds", p.cubature_seconds},
                       {"cubature_elements", p.cubature_elements},
                       {"training_error", p.training_error}});
    }
    report["reduction"] = {{"size", reduced->size()}, {"cubature_elements", reduced->cubature_elements()},
                           {"example_poses", poses}};
    if (log) *log << "pose-space reduction: r = " << reduced->size() << ", " << examples.size() << " example poses, "
                  << reduced->cubature_elements() << " cubature elements\n";
  } else {
    full = std::make_unique<MovingRestDynamics>(rig, arm.body, spec.dynamics);
  }

  const std::filesystem::path folder(out_dir);
  std::filesystem::create_directories(folder / "frames");
  std::vector<std::pair<double, std::string>> frames;
  std::vector<double> times, marker_jiggle, max_jiggle;
  auto write_frame = [&](int step, double time, const Vector& u) {
    const PoseMotion m = trajectory(time);
    const Vector rest = rig.rest_shape(m.p);
    Eigen::MatrixXd positions(mesh.num_vertices(), 3), rig_layer(mesh.num_vertices(), 3), dynamic(mesh.num_vertices(), 3);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      rig_layer.row(v) = rest.segment<3>(3 * v).transpose() - mesh.rest_positions.row(v);
      dynamic.row(v) = u.segment<3>(3 * v).transpose();
      positions.row(v) = (rest + u).segment<3>(3 * v).transpose();
    }
    VtkFields fields;
    fields.point["rig_displacement"] = rig_layer;
    fields.point["dynamic_displacement"] = dynamic;
    std::ostringstream name;
    name << "frame_" << std::setw(5) << std::setfill('0') << step << ".vtu";
    write_vtu((folder / "frames" / name.str()).string(), mesh, fields, &positions);
    frames.emplace_back(time, "frames/" + name.str());
  };
  auto record = [&](double time, const Vector& u) {
    times.push_back(time);
    marker_jiggle.push_back(u.segment<3>(3 * marker).norm());
    double largest = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v) largest = std::max(largest, u.segment<3>(3 * v).norm());
    max_jiggle.push_back(largest);
    run.max_jiggle = std::max(run.max_jiggle, largest);
  };

  const int steps = static_cast<int>(std::lround(spec.duration / spec.dynamics.time_step));
  const auto stepping = std::chrono::steady_clock::now();
  MovingRestState fs;
  ReducedRigState rs;
  Vector u = Vector::Zero(3 * mesh.num_vertices());
  if (full) fs = full->initial_state();
  if (reduced) rs = reduced->initial_state();
  record(0.0, u);
  write_frame(0, 0.0, u);
  run.completed = true;
  double step_seconds = 0.0;
  for (int k = 1; k <= steps; ++k) {
    int iterations = 0;
    bool ok = false;
    double time = 0.0;
    const auto t = std::chrono::steady_clock::now();
    if (full) {
      MovingRestState next;
      ok = full->step(trajectory, fs, next, iterations, run.message);
      if (ok) fs = next, u = fs.u, time = fs.time;
    } else {
      ReducedRigState next;
      ok = reduced->step(trajectory, rs, next, iterations, run.message);
      if (ok) rs = next, time = rs.time;
      step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
      if (ok) u = reduced->displacement(trajectory(time).p, rs.q);
    }
    if (full) step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    if (!ok) {
      run.completed = false;
      if (log) *log << run.message << "\n";
      break;
    }
    run.steps = k;
    record(time, u);
    if (k % spec.output_every == 0 || k == steps) write_frame(k, time, u);
  }
  (void)stepping;

  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [time, file] : frames)
    pvd << "    <DataSet timestep=\"" << std::setprecision(17) << time << "\" file=\"" << file << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  write_text_file_atomically((folder / "result.pvd").string(), pvd.str());

  LinePlot plot;
  plot.title = spec.name + ": jiggle (displacement from the rigged shape)";
  plot.x_label = "time [s]";
  plot.y_label = "|u|";
  plot.series.push_back({"marker vertex", Rgb{31, 119, 180}, times, marker_jiggle});
  plot.series.push_back({"largest over the mesh", Rgb{214, 39, 40}, times, max_jiggle});
  write_line_plot_png((folder / "jiggle.png").string(), plot);

  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report["dynamics"] = {{"time_step", spec.dynamics.time_step},
                        {"steps", run.steps},
                        {"completed", run.completed},
                        {"message", run.message},
                        {"step_seconds", step_seconds},
                        {"steps_per_second", step_seconds > 0 ? run.steps / step_seconds : 0.0},
                        {"max_jiggle", run.max_jiggle},
                        {"marker_vertex", marker}};
  report["outputs"] = {{"series", "result.pvd"}, {"plot", "jiggle.png"}, {"frames", frames.size()}};
  report["seconds"] = run.seconds;
  write_report(out_dir, report);
  if (log)
    *log << spec.name << ": " << run.steps << " steps (" << (spec.reduced ? "pose-space reduced" : "full space")
         << "), largest jiggle " << run.max_jiggle << ", " << frames.size() << " frames in " << out_dir << "\n";
  return run;
}

}  // namespace tailor
