// Parsing and solving rigid-body contact scenes (see rigid_scene.hpp).
#include "problems/contact/rigid_scene.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/contact/intersection.hpp"
#include "forward/core/model.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "objectives/target_positions.hpp"
#include "problems/contact/surface_vtu.hpp"
#include "problems/report_header.hpp"
#include "problems/taylor_report.hpp"
#include "problems/scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

rigid::RigidBody parse_body(const SceneNode& node, const std::string& source, std::vector<int>& fixed_dofs) {
  node.expect_keys({"name", "primitive", "mesh", "size", "radius", "subdivisions", "density", "position",
                    "velocity", "angular_velocity", "rotation", "fixed", "fixed_dofs"});
  Eigen::MatrixX3d vertices;
  Eigen::MatrixX3i faces;
  if (node.has("mesh")) {
    // The boundary of a tetrahedral mesh file (path relative to the scene file).
    const std::filesystem::path path = std::filesystem::path(source).parent_path() / node.at("mesh").string();
    const Mesh mesh = read_mesh(path.string());
    if (mesh.dim() != 3) node.at("mesh").fail("expected a 3D tetrahedral mesh");
    const Eigen::MatrixXi facets = boundary_facets(mesh);
    std::vector<int> index(static_cast<std::size_t>(mesh.num_vertices()), -1);
    std::vector<Eigen::Vector3d> used;
    faces.resize(facets.rows(), 3);
    for (int f = 0; f < facets.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        int& i = index[static_cast<std::size_t>(facets(f, k))];
        if (i < 0) {
          i = static_cast<int>(used.size());
          used.push_back(mesh.rest_positions.row(facets(f, k)).transpose());
        }
        faces(f, k) = i;
      }
    vertices.resize(static_cast<Eigen::Index>(used.size()), 3);
    for (std::size_t i = 0; i < used.size(); ++i)
      vertices.row(static_cast<Eigen::Index>(i)) = used[i].transpose();
  } else {
    const std::string primitive = node.at("primitive").choice({"box", "sphere"});
    if (primitive == "box") {
      rigid::box_surface(node.at("size").vector(3), vertices, faces);
    } else {
      const int subdivisions = node.has("subdivisions") ? node.at("subdivisions").integer(0) : 2;
      if (subdivisions > 6) node.at("subdivisions").fail("at most 6 subdivisions");
      rigid::sphere_surface(node.at("radius").positive(), subdivisions, vertices, faces);
    }
  }
  const double density = node.has("density") ? node.at("density").positive() : 1000.0;
  const bool fixed = node.has("fixed") && node.at("fixed").boolean();
  rigid::RigidBody body;
  try {
    body = rigid::rigid_body_from_mesh(node.has("name") ? node.at("name").string() : "", vertices, faces,
                                       density, fixed);
  } catch (const std::invalid_argument& e) {
    node.fail(e.what());
  }
  // A primitive is placed by its centre; a mesh keeps its own coordinates unless positioned.
  if (!node.has("mesh")) body.position.setZero();
  if (node.has("position")) body.position = node.at("position").vector(3);
  if (node.has("rotation")) body.rotation = node.at("rotation").vector(3);
  if (body.rotation.norm() >= M_PI)
    node.at("rotation").fail("the rotation vector's angle must stay below pi");
  fixed_dofs.clear();
  if (node.has("fixed_dofs"))
    for (const SceneNode& item : node.at("fixed_dofs").items()) {
      const std::string dof = item.choice({"x", "y", "z", "rx", "ry", "rz"});
      const char* names[] = {"x", "y", "z", "rx", "ry", "rz"};
      for (int k = 0; k < 6; ++k)
        if (dof == names[k]) fixed_dofs.push_back(k);
    }
  return body;
}

}  // namespace

bool is_rigid_scene(const std::string& path) {
  std::ifstream in(path);
  if (!in) return false;
  const nlohmann::json document = nlohmann::json::parse(in, nullptr, false);
  return document.is_object() && document.contains("rigid_bodies");
}

RigidSceneSpec parse_rigid_scene(const std::string& json_text, const std::string& source) {
  const nlohmann::json document = nlohmann::json::parse(json_text, nullptr, false);
  if (document.is_discarded()) throw SceneError(source + ": invalid JSON");
  const SceneNode root(document, source, "");
  root.expect_keys({"name", "description", "rigid_bodies", "gravity", "contact", "newton", "dynamics"});
  RigidSceneSpec spec;
  spec.source = source;
  if (root.has("name")) spec.name = root.at("name").string();
  if (root.has("description")) spec.description = root.at("description").string();
  const std::vector<SceneNode> bodies = root.at("rigid_bodies").items();
  if (bodies.empty()) root.at("rigid_bodies").fail("expected at least one body");
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    std::vector<int> fixed;
    spec.bodies.push_back(parse_body(bodies[b], source, fixed));
    if (spec.bodies.back().name.empty()) spec.bodies.back().name = "body" + std::to_string(b);
    spec.fixed_body_dofs.push_back(fixed);
    spec.velocities.push_back(bodies[b].has("velocity") ? Eigen::Vector3d(bodies[b].at("velocity").vector(3))
                                                        : Eigen::Vector3d::Zero());
    spec.angular_velocities.push_back(bodies[b].has("angular_velocity")
                                          ? Eigen::Vector3d(bodies[b].at("angular_velocity").vector(3))
                                          : Eigen::Vector3d::Zero());
  }
  if (root.has("dynamics")) {
    const SceneNode d = root.at("dynamics");
    d.expect_keys({"time_step", "steps", "output_every"});
    spec.time_step = d.at("time_step").positive();
    spec.steps = d.at("steps").integer(1);
    if (d.has("output_every")) spec.output_every = d.at("output_every").integer(1);
  }
  if (root.has("gravity")) spec.gravity = root.at("gravity").vector(3);
  if (root.has("contact")) {
    const SceneNode c = root.at("contact");
    c.expect_keys({"activation_distance", "stiffness", "friction", "ccd_separation"});
    if (c.has("activation_distance"))
      spec.contact.activation_distance = c.at("activation_distance").positive();
    if (c.has("stiffness")) spec.contact.stiffness = c.at("stiffness").positive();
    if (c.has("ccd_separation"))
      spec.contact.ccd.separation_fraction = c.at("ccd_separation").open_interval(0, 1);
    if (c.has("friction") && c.at("friction").non_negative() != 0.0)
      c.at("friction").fail("friction is not implemented yet (static equilibrium is frictionless)");
  }
  if (root.has("newton")) {
    const SceneNode n = root.at("newton");
    n.expect_keys({"max_iterations", "relative_tolerance"});
    if (n.has("max_iterations")) spec.newton.max_iterations = n.at("max_iterations").integer(1);
    if (n.has("relative_tolerance"))
      spec.newton.relative_tolerance = n.at("relative_tolerance").open_interval(0, 1);
  }
  return spec;
}

RigidSceneSpec read_rigid_scene(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::stringstream text;
  text << in.rdbuf();
  RigidSceneSpec spec = parse_rigid_scene(text.str(), path);
  if (spec.name.empty()) spec.name = std::filesystem::path(path).stem().string();
  return spec;
}

namespace {

// Gravity and contact over the scene's bodies, fixed and held DOFs eliminated. With
// `mass_parameters`, the masses are the parameter block "mass".
struct RigidSceneModel {
  rigid::RigidBodySystem system;
  Model model;
  const rigid::RigidContactTerm* contact = nullptr;
  rigid::RigidInertiaTerm* inertia = nullptr;  // dynamic scenes
  RigidSceneModel(const RigidSceneSpec& spec, bool mass_parameters)
      : system(spec.bodies), model(system.num_dofs()) {
    if (mass_parameters) model.parameter_layout().add("mass", system.num_bodies());
    if (spec.time_step > 0.0)
      inertia = &model.add(std::make_unique<rigid::RigidInertiaTerm>(system, spec.time_step));
    model.add(std::make_unique<rigid::RigidGravityTerm>(system, spec.gravity, mass_parameters ? 0 : -1));
    contact = &model.add(std::make_unique<rigid::RigidContactTerm>(system, spec.contact));
    std::vector<int> fixed = system.fixed_dofs();
    for (int b = 0; b < system.num_bodies(); ++b)
      if (!system.body(b).fixed)
        for (int k : spec.fixed_body_dofs[static_cast<std::size_t>(b)]) fixed.push_back(6 * b + k);
    model.set_elimination(Elimination::dirichlet(fixed, system.initial_state()));
    const double start_distance = contact->min_distance(system.initial_state(), 1e30);
    const int crossings = contact::count_edge_face_intersections(
        system.surface(), system.world_positions(system.initial_state()));
    if (!(start_distance > 0.0) || crossings > 0)
      throw SceneError(spec.source + ": bodies touch or intersect in the initial state (distance " +
                       std::to_string(start_distance) + ", " + std::to_string(crossings) +
                       " edge-face crossings)");
  }
};

// Every body's surface at state q as DIR/<body><suffix>.vtu.
void write_frames(const rigid::RigidBodySystem& system, const Vector& q, const std::string& out_dir,
                  const std::string& suffix) {
  const contact::Positions x = system.world_positions(q);
  int first = 0;
  for (int b = 0; b < system.num_bodies(); ++b) {
    const auto rows = static_cast<Eigen::Index>(system.body(b).vertices.rows());
    write_surface_vtu((std::filesystem::path(out_dir) / (system.body(b).name + suffix + ".vtu")).string(),
                      x.middleRows(first, rows), system.body(b).faces);
    first += static_cast<int>(rows);
  }
}

nlohmann::json body_states(const rigid::RigidBodySystem& system, const Vector& q, const Vector& forces) {
  nlohmann::json bodies = nlohmann::json::array();
  auto triple = [](const Vector& v, int offset) {
    return std::vector<double>{v[offset], v[offset + 1], v[offset + 2]};
  };
  for (int b = 0; b < system.num_bodies(); ++b)
    bodies.push_back({{"name", system.body(b).name},
                      {"mass", system.body(b).mass},
                      {"position", triple(q, 6 * b)},
                      {"rotation", triple(q, 6 * b + 3)},
                      {"contact_force", triple(forces, 6 * b)},
                      {"contact_moment", triple(forces, 6 * b + 3)}});
  return bodies;
}

RigidSimulateRun simulate_dynamics(const RigidSceneSpec& spec, RigidSceneModel& scene,
                                   const std::string& out_dir, std::ostream* log) {
  const rigid::RigidBodySystem& system = scene.system;
  rigid::RigidTimeStepper stepper(system, scene.model, *scene.inertia, spec.newton);
  for (int b = 0; b < system.num_bodies(); ++b)
    stepper.set_velocity(b, spec.velocities[static_cast<std::size_t>(b)],
                         spec.angular_velocities[static_cast<std::size_t>(b)]);
  std::filesystem::create_directories(out_dir);
  auto frame_suffix = [](int n) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "_%04d", n);
    return std::string(buffer);
  };
  write_frames(system, stepper.state(), out_dir, frame_suffix(0));
  RigidSimulateRun run;
  run.min_distance = std::numeric_limits<double>::infinity();
  nlohmann::json steps = nlohmann::json::array();
  int total_iterations = 0;
  for (int n = 1; n <= spec.steps; ++n) {
    run.newton = stepper.step();
    if (!run.newton.converged()) {
      if (log) *log << "step " << n << " failed:\n" << run.newton.report() << "\n";
      break;
    }
    run.steps_completed = n;
    total_iterations += run.newton.iterations;
    const double distance = scene.contact->min_distance(stepper.state(), 1e30);
    const int crossings =
        contact::count_edge_face_intersections(system.surface(), system.world_positions(stepper.state()));
    run.min_distance = std::min(run.min_distance, distance);
    run.intersections += crossings;
    steps.push_back({{"step", n},
                     {"newton_iterations", run.newton.iterations},
                     {"min_distance", distance},
                     {"intersections", crossings}});
    if (log)
      *log << "step " << n << ": " << run.newton.iterations << " Newton iterations, min distance " << distance
           << (crossings ? ", INTERSECTING" : "") << "\n";
    if (n % spec.output_every == 0) write_frames(system, stepper.state(), out_dir, frame_suffix(n));
  }
  run.state = stepper.state();
  run.contact_forces = Vector::Zero(run.state.size());
  scene.contact->add_gradient(run.state, Vector(), run.contact_forces);
  run.contact_forces = -run.contact_forces;
  run.active_pairs = scene.contact->potential().num_active(system.world_positions(run.state));
  nlohmann::ordered_json report;
  add_report_header(report);
  report["scene"] = spec.name;
  report["status"] = run.completed() && run.steps_completed == spec.steps ? "completed" : "failed";
  report["time_step"] = spec.time_step;
  report["steps"] = spec.steps;
  report["steps_completed"] = run.steps_completed;
  report["newton_iterations"] = total_iterations;
  report["min_distance"] = run.min_distance;
  report["intersections"] = run.intersections;
  report["per_step"] = steps;
  report["bodies"] = body_states(system, run.state, run.contact_forces);
  std::ofstream(std::filesystem::path(out_dir) / "report.json") << report.dump(2) << "\n";
  return run;
}

}  // namespace

RigidSimulateRun simulate_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir,
                                      std::ostream* log) {
  RigidSceneModel scene(spec, false);
  if (spec.time_step > 0.0) return simulate_dynamics(spec, scene, out_dir, log);
  const rigid::RigidBodySystem& system = scene.system;
  const Model& model = scene.model;
  const rigid::RigidContactTerm& contact = *scene.contact;
  const Vector q0 = system.initial_state();

  RigidSimulateRun run;
  NewtonOptions options = spec.newton;
  options.progress = log;
  NewtonSolver newton(model, options);
  Vector y = model.elimination().restrict_state(q0);
  run.newton = newton.solve(Vector(), y);
  run.state = model.state(y, Vector());
  run.contact_forces = Vector::Zero(run.state.size());
  contact.add_gradient(run.state, Vector(), run.contact_forces);
  run.contact_forces = -run.contact_forces;
  run.min_distance = contact.min_distance(run.state, 1e30);
  run.active_pairs = contact.potential().num_active(system.world_positions(run.state));
  if (log)
    *log << run.newton.report() << "\nmin distance between bodies " << run.min_distance
         << ", active contact pairs " << run.active_pairs << "\n";

  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json report;
  add_report_header(report);
  report["scene"] = spec.name;
  report["status"] = to_string(run.newton.status);
  report["iterations"] = run.newton.iterations;
  report["final_residual"] = run.newton.final_residual;
  report["seconds"] = run.newton.total_seconds;
  report["min_distance"] = run.min_distance;
  report["active_pairs"] = run.active_pairs;
  report["bodies"] = body_states(system, run.state, run.contact_forces);
  write_frames(system, run.state, out_dir, "");
  std::ofstream(std::filesystem::path(out_dir) / "report.json") << report.dump(2) << "\n";
  return run;
}

TaylorTestResult gradcheck_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir, unsigned seed,
                                       std::ostream* log) {
  if (spec.time_step > 0.0)
    throw SceneError(spec.source +
                     ": gradcheck of dynamic rigid scenes is not implemented (static scenes only)");
  RigidSceneModel scene(spec, true);
  const rigid::RigidBodySystem& system = scene.system;
  std::vector<int> centres;
  for (int b = 0; b < system.num_bodies(); ++b)
    if (!system.body(b).fixed) centres.push_back(2 * b);  // block 2b of 3 DOFs is T_b
  if (centres.empty())
    throw SceneError(spec.source + ": gradcheck needs at least one body that is not fixed");
  Matrix targets(static_cast<Eigen::Index>(centres.size()), 3);
  for (std::size_t i = 0; i < centres.size(); ++i)
    targets.row(static_cast<Eigen::Index>(i)) = system.body(centres[i] / 2).position.transpose();
  auto objective = std::make_shared<TargetPositions>(3, centres, targets);
  StaticFunctionalOptions options;
  options.newton = spec.newton;
  options.newton.relative_tolerance = std::min(spec.newton.relative_tolerance, 1e-11);
  StaticFunctional functional(scene.model, identity_map(system.num_bodies()), objective,
                              scene.model.elimination().restrict_state(system.initial_state()), options);
  Vector masses(system.num_bodies());
  for (int b = 0; b < system.num_bodies(); ++b) masses[b] = system.body(b).mass;
  TaylorTestOptions taylor;
  taylor.seed = seed;
  const TaylorTestResult result = taylor_test(functional, masses, taylor);
  if (log) *log << "gradient of 1/2 sum |T_b - T_b^0|^2 with respect to the body masses\n" << result.table();
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json document = taylor_json(result);
  add_report_header(document);
  document["scene"] = {{"name", spec.name}, {"source", spec.source}};
  std::ofstream(std::filesystem::path(out_dir) / "gradcheck.json") << document.dump(2) << "\n";
  return result;
}

}  // namespace tailor
