// Solving contact scenes: static equilibrium of rigid and FEM bodies, implicit Euler steps of
// rigid bodies (see rigid_scene.hpp).
#include "problems/contact/rigid_scene.hpp"

#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>

#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/contact/intersection.hpp"
#include "forward/core/model.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "forward/rigid/free_motions.hpp"
#include "forward/rigid/friction_term.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_load_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "objectives/target_positions.hpp"
#include "problems/contact/embedded_term.hpp"
#include "problems/contact/fem_bodies.hpp"
#include "problems/contact/surface_vtu.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {
namespace {

// The scene as a Model: rigid DOFs 6b .. 6b+5 first, then each FEM body's vertex DOFs; gravity,
// loads, FEM elasticity and loads (EmbeddedTerm), contact over all surfaces (ContactBodies),
// friction and inertia in dynamic scenes; fixed, kinematic and held DOFs and the FEM bodies'
// Dirichlet DOFs eliminated. With `mass_parameters`, the masses are the parameter block "mass".
struct RigidSceneModel {
  rigid::RigidBodySystem system;
  std::vector<FemBodyPart> fem;
  std::unique_ptr<Model> model;
  Vector rest_state, parameters;
  rigid::RigidContactTerm* contact = nullptr;
  rigid::RigidInertiaTerm* inertia = nullptr;  // dynamic scenes
  rigid::FrictionTerm* friction = nullptr;     // dynamic scenes with friction
  rigid::RigidLoadTerm* loads = nullptr;       // forces or torques
  double fem_load = 0.0;                       // the largest total load on one FEM body [force]

  RigidSceneModel(const RigidSceneSpec& spec, bool mass_parameters) : system(spec.bodies) {
    int num_dofs = system.num_dofs(), num_parameters = 0;
    for (const FemBodySpec& body : spec.fem_bodies) {
      fem.push_back(build_fem_body(body, num_dofs, num_parameters));
      num_dofs += fem.back().setup.num_dofs();
      num_parameters += static_cast<int>(fem.back().parameters.size());
    }
    model = std::make_unique<Model>(num_dofs);
    rest_state = Vector(num_dofs);
    rest_state.head(system.num_dofs()) = system.initial_state();
    parameters = Vector(num_parameters);
    std::vector<rigid::DeformableSurface> surfaces;
    std::vector<int> fixed = system.fixed_dofs();
    for (int b = 0; b < system.num_bodies(); ++b)
      if (!system.body(b).fixed && !system.body(b).kinematic)
        for (int k : spec.fixed_body_dofs[static_cast<std::size_t>(b)]) fixed.push_back(6 * b + k);
    Vector fixed_values = rest_state;
    for (FemBodyPart& part : fem) {
      const int n = part.setup.num_dofs(), m = static_cast<int>(part.parameters.size());
      rest_state.segment(part.dof_offset, n) = part.setup.rest_state();
      fixed_values.segment(part.dof_offset, n) = part.model->elimination().offset();
      parameters.segment(part.parameter_offset, m) = part.parameters;
      for (const auto& term : part.model->terms())
        model->add(std::make_unique<EmbeddedTerm>(*term, part.dof_offset, n, part.parameter_offset, m));
      for (int dof : part.setup.fixed_dofs) fixed.push_back(part.dof_offset + dof);
      const Vector& f = part.setup.nodal_forces;
      fem_load = std::max(
          fem_load, Eigen::Map<const Eigen::MatrixXd>(f.data(), 3, f.size() / 3).rowwise().sum().norm());
      rigid::DeformableSurface surface;
      surface.name = part.name;
      surface.faces = part.faces;
      for (int v : part.mesh_vertex) surface.vertex_dofs.push_back(part.dof_offset + 3 * v);
      surfaces.push_back(std::move(surface));
    }
    for (int b = 0; b < system.num_bodies(); ++b)
      fixed_values.segment<6>(6 * b) = rest_state.segment<6>(6 * b);
    if (mass_parameters) model->parameter_layout().add("mass", system.num_bodies());
    if (spec.time_step > 0.0)
      inertia = &model->add(std::make_unique<rigid::RigidInertiaTerm>(system, spec.time_step));
    model->add(std::make_unique<rigid::RigidGravityTerm>(system, spec.gravity, mass_parameters ? 0 : -1));
    Vector body_loads = Vector::Zero(system.num_dofs());
    for (int b = 0; b < system.num_bodies(); ++b) {
      body_loads.segment<3>(6 * b) = spec.forces[static_cast<std::size_t>(b)];
      body_loads.segment<3>(6 * b + 3) = spec.torques[static_cast<std::size_t>(b)];
    }
    if (body_loads.squaredNorm() > 0.0)  // over the rigid DOFs, the first of the state
      loads = &model->add(std::make_unique<rigid::RigidLoadTerm>(body_loads, system.initial_state()));
    auto bodies = std::make_shared<const rigid::ContactBodies>(system, std::move(surfaces), num_dofs);
    contact = &model->add(std::make_unique<rigid::RigidContactTerm>(bodies, rest_state, spec.contact));
    if (spec.friction.coefficient > 0.0)
      friction = &model->add(std::make_unique<rigid::FrictionTerm>(*contact, spec.friction));
    model->set_elimination(Elimination::dirichlet(fixed, fixed_values));
    if (!(spec.time_step > 0.0)) require_held(spec, *bodies, fixed);
    const double start_distance = contact->min_distance(rest_state, 1e30);
    const int crossings =
        contact::count_edge_face_intersections(bodies->surface(), bodies->positions(rest_state));
    if (!(start_distance > 0.0) || crossings > 0)
      throw SceneError(spec.source + ": bodies touch or intersect in the initial state (distance " +
                       std::to_string(start_distance) + ", " + std::to_string(crossings) +
                       " edge-face crossings)");
  }

  // A static scene needs every motion of all bodies together to be stopped by a fixed body, a
  // held DOF or an FEM body's support: contact resists only relative motion (docs/contact.md).
  void require_held(const RigidSceneSpec& spec, const rigid::ContactBodies& bodies,
                    const std::vector<int>& held) const {
    std::vector<std::pair<int, Eigen::Vector3d>> points;
    for (const FemBodyPart& part : fem)
      for (int v = 0; v < part.setup.mesh.num_vertices(); ++v)
        points.emplace_back(part.dof_offset + 3 * v, rest_state.segment<3>(part.dof_offset + 3 * v));
    const contact::Positions x = bodies.positions(rest_state);
    const Eigen::Vector3d low = x.colwise().minCoeff(), high = x.colwise().maxCoeff();
    const Eigen::Vector3d centre = 0.5 * (low + high);
    const Matrix motions = rigid::rigid_system_motions(system, rest_state, model->num_dofs(), points, centre);
    const std::vector<rigid::FreeMotion> free = rigid::free_motions(motions, held, (high - low).norm());
    if (free.empty()) return;
    std::vector<std::string> movable;
    for (int b = 0; b < system.num_bodies(); ++b)
      if (!system.body(b).fixed && !system.body(b).kinematic) movable.push_back(system.body(b).name);
    const std::string what = movable.size() == 1 && fem.empty()
                                 ? "body \"" + movable[0] + "\" is free to move rigidly"
                                 : "bodies are free to move together as one rigid body";
    throw SceneError(spec.source + ": the " + what + " (" +
                     rigid::describe_free_motions(free, centre) +
                     "): no fixed body, held DOF (\"fixed_dofs\") or FEM support stops it, and contact only "
                     "resists relative motion, so the static problem has no equilibrium; fix a body "
                     "(\"fixed\": true), hold DOFs, or simulate it with a \"dynamics\" section");
  }
};

int intersections(const RigidSceneModel& scene, const Vector& q) {
  return contact::count_edge_face_intersections(scene.contact->bodies().surface(),
                                                scene.contact->bodies().positions(q));
}

// Every body's surface at state q as DIR/<body><suffix>.vtu (FEM bodies: their deformed mesh).
void write_frames(const RigidSceneModel& scene, const Vector& q, const std::string& out_dir,
                  const std::string& suffix) {
  const rigid::RigidBodySystem& system = scene.system;
  const contact::Positions x = system.world_positions(q.head(system.num_dofs()));
  int first = 0;
  for (int b = 0; b < system.num_bodies(); ++b) {
    const auto rows = static_cast<Eigen::Index>(system.body(b).vertices.rows());
    write_surface_vtu((std::filesystem::path(out_dir) / (system.body(b).name + suffix + ".vtu")).string(),
                      x.middleRows(first, rows), system.body(b).faces);
    first += static_cast<int>(rows);
  }
  for (const FemBodyPart& part : scene.fem) {
    const Vector u = q.segment(part.dof_offset, part.setup.num_dofs());
    const Eigen::MatrixXd positions =
        Eigen::Map<const Eigen::MatrixXd>(u.data(), 3, part.setup.mesh.num_vertices()).transpose();
    write_vtu((std::filesystem::path(out_dir) / (part.name + suffix + ".vtu")).string(), part.setup.mesh, {},
              &positions);
  }
}

// Contact forces: -dB/dq per DOF, the true moment about each rigid body's centre, the total on
// each FEM body.
void contact_results(const RigidSceneModel& scene, RigidSimulateRun& run) {
  const rigid::RigidContactTerm& contact = *scene.contact;
  run.contact_forces = Vector::Zero(run.state.size());
  contact.add_gradient(run.state, scene.parameters, run.contact_forces);
  run.contact_forces = -run.contact_forces;
  const rigid::ContactBodies& bodies = contact.bodies();
  const contact::Positions x = bodies.positions(run.state), f = contact.vertex_forces(run.state);
  run.contact_moments.assign(static_cast<std::size_t>(scene.system.num_bodies()), Eigen::Vector3d::Zero());
  run.fem_contact_forces.assign(scene.fem.size(), Eigen::Vector3d::Zero());
  for (int v = 0; v < bodies.surface().num_vertices; ++v) {
    const int b = bodies.body_of(v);
    if (b >= 0)
      run.contact_moments[static_cast<std::size_t>(b)] +=
          (x.row(v).transpose() - run.state.segment<3>(6 * b)).cross(f.row(v).transpose());
  }
  for (std::size_t i = 0; i < scene.fem.size(); ++i) {
    const int first = bodies.deformable_offset(static_cast<int>(i));
    for (std::size_t k = 0; k < scene.fem[i].mesh_vertex.size(); ++k)
      run.fem_contact_forces[i] += f.row(first + static_cast<int>(k)).transpose();
  }
  run.active_pairs = contact.potential().num_active(x);
  run.stiffness = contact.potential().options().stiffness;
}

// vee of the skew part of A (the angular velocity of Rdot R^T).
Eigen::Vector3d skew_vee(const Eigen::Matrix3d& A) {
  return 0.5 * Eigen::Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
}

nlohmann::json triple(const Eigen::Vector3d& v) { return std::vector<double>{v.x(), v.y(), v.z()}; }

nlohmann::json body_states(const RigidSceneModel& scene, const RigidSimulateRun& run) {
  nlohmann::json bodies = nlohmann::json::array();
  const rigid::RigidBodySystem& system = scene.system;
  for (int b = 0; b < system.num_bodies(); ++b)
    bodies.push_back({{"name", system.body(b).name},
                      {"mass", system.body(b).mass},
                      {"position", triple(run.state.segment<3>(6 * b))},
                      {"rotation", triple(run.state.segment<3>(6 * b + 3))},
                      {"contact_force", triple(run.contact_forces.segment<3>(6 * b))},
                      {"contact_moment", triple(run.contact_moments[static_cast<std::size_t>(b)])}});
  if (!run.velocities.empty())
    for (int b = 0; b < system.num_bodies(); ++b) {
      bodies[static_cast<std::size_t>(b)]["velocity"] = triple(run.velocities[static_cast<std::size_t>(b)]);
      bodies[static_cast<std::size_t>(b)]["angular_velocity"] =
          triple(run.angular_velocities[static_cast<std::size_t>(b)]);
    }
  return bodies;
}

nlohmann::json fem_states(const RigidSceneModel& scene, const RigidSimulateRun& run) {
  nlohmann::json bodies = nlohmann::json::array();
  for (std::size_t i = 0; i < scene.fem.size(); ++i) {
    const FemBodyPart& part = scene.fem[i];
    const Vector u = run.state.segment(part.dof_offset, part.setup.num_dofs()) - part.setup.rest_state();
    double largest = 0.0;
    for (int v = 0; v < part.setup.mesh.num_vertices(); ++v)
      largest = std::max(largest, u.segment<3>(3 * v).norm());
    bodies.push_back({{"name", part.name},
                      {"vertices", part.setup.mesh.num_vertices()},
                      {"elements", part.setup.mesh.num_elements()},
                      {"surface_vertices", part.mesh_vertex.size()},
                      {"max_displacement", largest},
                      {"contact_force", triple(run.fem_contact_forces[i])}});
  }
  return bodies;
}

// Adaptive kappa's bounds: the given ones, else min = the kappa at which one pair at d_hat / 2
// carries 1 % of the largest load on one body (contact::stiffness_for_force; the load: a free
// rigid body's weight and force, an FEM body's total load; in dynamics at least m d_hat / h^2,
// the force that stops a body moving d_hat per step within the step; 1 when there is none) and
// max = 100 min (IPC's ratio): one pair then carries the whole load at d_hat / 2.
contact::StiffnessOptions stiffness_options(const RigidSceneSpec& spec, double fem_load) {
  contact::StiffnessOptions s = spec.stiffness;
  if (!(s.min_stiffness > 0.0)) {
    double force = fem_load;
    for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
      const rigid::RigidBody& body = spec.bodies[b];
      if (body.fixed || body.kinematic) continue;
      force = std::max(force, body.mass * spec.gravity.norm() + spec.forces[b].norm());
      if (spec.time_step > 0.0)
        force =
            std::max(force, body.mass * spec.contact.activation_distance / (spec.time_step * spec.time_step));
    }
    s.min_stiffness =
        contact::stiffness_for_force(0.01 * (force > 0.0 ? force : 1.0), spec.contact.activation_distance);
  }
  if (!(s.max_stiffness > 0.0)) s.max_stiffness = 100.0 * s.min_stiffness;
  return s;
}

nlohmann::json stiffness_json(const RigidSceneSpec& spec, const RigidSceneModel& scene, double kappa) {
  nlohmann::json s = {{"mode", spec.stiffness.adaptive ? "adaptive" : "fixed"}, {"final", kappa}};
  if (spec.stiffness.adaptive) {
    const contact::StiffnessOptions bounds = stiffness_options(spec, scene.fem_load);
    s["min"] = bounds.min_stiffness;
    s["max"] = bounds.max_stiffness;
  }
  return s;
}

RigidSimulateRun simulate_dynamics(const RigidSceneSpec& spec, RigidSceneModel& scene,
                                   const std::string& out_dir, std::ostream* log) {
  const rigid::RigidBodySystem& system = scene.system;
  rigid::RigidStepOptions step_options;
  step_options.contact = scene.contact;
  step_options.friction = scene.friction;
  step_options.loads = scene.loads;
  step_options.initial_guess = spec.initial_guess;
  step_options.velocity_tolerance = spec.velocity_tolerance;
  if (spec.velocity_tolerance < 0.0) {
    const contact::Positions x = system.world_positions(system.initial_state());
    step_options.velocity_tolerance = 1e-8 * (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
  }
  step_options.friction_iterations = spec.friction_iterations;
  step_options.stiffness = stiffness_options(spec, scene.fem_load);
  rigid::RigidTimeStepper stepper(system, *scene.model, *scene.inertia, spec.newton, step_options);
  for (int b = 0; b < system.num_bodies(); ++b)
    if (!system.body(b).kinematic)
      stepper.set_velocity(b, spec.velocities[static_cast<std::size_t>(b)],
                           spec.angular_velocities[static_cast<std::size_t>(b)]);
  std::filesystem::create_directories(out_dir);
  auto frame_suffix = [](int n) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "_%04d", n);
    return std::string(buffer);
  };
  write_frames(scene, stepper.state(), out_dir, frame_suffix(0));
  RigidSimulateRun run;
  run.min_distance = std::numeric_limits<double>::infinity();
  nlohmann::json steps = nlohmann::json::array();
  for (int n = 1; n <= spec.steps; ++n) {
    run.newton = stepper.step();
    if (!run.newton.converged()) {
      // The failed step's iterations ran too (the report counts every Newton iteration).
      run.newton_iterations += stepper.last_report().newton_iterations;
      if (log) *log << "step " << n << " failed:\n" << run.newton.report() << "\n";
      break;
    }
    const rigid::RigidStepReport& report = stepper.last_report();
    run.steps_completed = n;
    run.newton_iterations += report.newton_iterations;
    const double distance = scene.contact->min_distance(stepper.state(), 1e30);
    const int crossings = intersections(scene, stepper.state());
    run.min_distance = std::min(run.min_distance, distance);
    run.intersections += crossings;
    nlohmann::json step = {{"step", n},
                           {"newton_iterations", report.newton_iterations},
                           {"min_distance", distance},
                           {"intersections", crossings},
                           {"stiffness", report.stiffness}};
    if (report.kinematic_stages > 1) step["kinematic_stages"] = report.kinematic_stages;
    if (scene.friction) {
      const auto [sliding, sticking] = scene.friction->sliding_and_sticking(stepper.state());
      step["sliding_pairs"] = sliding;
      step["sticking_pairs"] = sticking;
    }
    steps.push_back(step);
    if (log)
      *log << "step " << n << ": " << report.newton_iterations << " Newton iterations, min distance "
           << distance << ", kappa " << report.stiffness << (crossings ? ", INTERSECTING" : "") << "\n";
    if (n % spec.output_every == 0) write_frames(scene, stepper.state(), out_dir, frame_suffix(n));
  }
  run.state = stepper.state();
  for (const rigid::RigidMotion& m : stepper.motion()) {
    run.velocities.push_back(m.velocity);
    run.angular_velocities.push_back(skew_vee(m.rotation_rate * m.rotation.transpose()));
  }
  contact_results(scene, run);
  nlohmann::ordered_json report;
  add_report_header(report);
  report["scene"] = spec.name;
  report["status"] = run.completed() && run.steps_completed == spec.steps ? "completed" : "failed";
  report["time_step"] = spec.time_step;
  report["steps"] = spec.steps;
  report["steps_completed"] = run.steps_completed;
  report["newton_iterations"] = run.newton_iterations;
  report["min_distance"] = run.min_distance;
  report["intersections"] = run.intersections;
  report["stiffness"] = stiffness_json(spec, scene, run.stiffness);
  report["friction"] = {{"coefficient", spec.friction.coefficient},
                        {"velocity_threshold", spec.friction.velocity_threshold},
                        {"iterations", spec.friction_iterations}};
  report["velocity_tolerance"] = step_options.velocity_tolerance;
  report["per_step"] = steps;
  report["bodies"] = body_states(scene, run);
  write_report(out_dir, report);
  return run;
}

// Newton from q0 with the stiffness balanced there when adaptive; with torques, re-solved with
// their reference moved to the solution until the solution stays (at most 20 times; a solution
// still moving then is reported as max_iterations, not as converged).
void solve_static(const RigidSceneSpec& spec, RigidSceneModel& scene, std::ostream* log,
                  RigidSimulateRun& run) {
  Model& model = *scene.model;
  const Vector& p = scene.parameters;
  Vector y = model.elimination().restrict_state(scene.rest_state);
  if (spec.stiffness.adaptive) {
    const contact::StiffnessOptions s = stiffness_options(spec, scene.fem_load);
    const Vector q = model.state(y, p);
    const Vector barrier = scene.contact->unit_stiffness_gradient(q);
    const Vector other = model.gradient(q, p) - scene.contact->potential().options().stiffness * barrier;
    scene.contact->potential().set_stiffness(contact::balanced_stiffness(model.elimination().reduce(other),
                                                                         model.elimination().reduce(barrier),
                                                                         s.min_stiffness, s.max_stiffness));
  }
  NewtonOptions options = spec.newton;
  options.progress = log;
  if (spec.stiffness.adaptive) {
    // Raised while the smallest distance keeps shrinking below the threshold.
    const contact::StiffnessOptions s = stiffness_options(spec, scene.fem_load);
    const double d_hat = spec.contact.activation_distance;
    auto previous = std::make_shared<double>(scene.contact->min_distance(model.state(y, p), d_hat));
    rigid::RigidContactTerm* contact = scene.contact;
    options.after_step = [contact, previous, s, d_hat](const Vector& x) {
      const double distance = contact->min_distance(x, d_hat);
      contact->potential().set_stiffness(
          contact::raised_stiffness(contact->potential().options().stiffness, *previous, distance,
                                    s.distance_fraction * d_hat, s.growth, s.max_stiffness));
      *previous = distance;
    };
  }
  NewtonSolver newton(model, options);
  for (int lag = 0;; ++lag) {
    const Vector before = y;
    run.newton = newton.solve(p, y);
    run.newton_iterations += run.newton.iterations;
    if (lag == 0) newton.options().reference_residual = run.newton.initial_residual;
    if (!run.newton.converged() || !scene.loads || !scene.loads->has_torques()) break;
    scene.loads->set_reference(model.state(y, p).head(scene.system.num_dofs()));
    if ((y - before).lpNorm<Eigen::Infinity>() <= 1e-14 * (1.0 + y.lpNorm<Eigen::Infinity>())) break;
    if (lag == 20) {  // the torques' reference still moves: not the equilibrium of the torques
      run.newton.status = NewtonStatus::max_iterations;
      run.newton.message = "the solution still moved after 21 solves with the torques' reference moved to it";
      break;
    }
  }
  run.state = model.state(y, p);
}

}  // namespace

RigidSimulateRun simulate_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir,
                                      std::ostream* log) {
  RigidSceneModel scene(spec, false);
  if (spec.time_step > 0.0) return simulate_dynamics(spec, scene, out_dir, log);
  RigidSimulateRun run;
  solve_static(spec, scene, log, run);
  contact_results(scene, run);
  run.min_distance = scene.contact->min_distance(run.state, 1e30);
  run.intersections = intersections(scene, run.state);
  if (log)
    *log << run.newton.report() << "\nmin distance between bodies " << run.min_distance
         << ", active contact pairs " << run.active_pairs << ", kappa " << run.stiffness
         << (run.intersections ? ", INTERSECTING" : "") << "\n";

  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json report;
  add_report_header(report);
  report["scene"] = spec.name;
  report["status"] = to_string(run.newton.status);
  report["iterations"] = run.newton_iterations;
  report["final_residual"] = run.newton.final_residual;
  report["seconds"] = run.newton.total_seconds;
  report["min_distance"] = run.min_distance;
  report["intersections"] = run.intersections;
  report["active_pairs"] = run.active_pairs;
  report["stiffness"] = stiffness_json(spec, scene, run.stiffness);
  report["bodies"] = body_states(scene, run);
  if (!scene.fem.empty()) report["fem_bodies"] = fem_states(scene, run);
  write_frames(scene, run.state, out_dir, "");
  write_report(out_dir, report);
  return run;
}

TaylorTestResult gradcheck_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir, unsigned seed,
                                       std::ostream* log) {
  if (spec.time_step > 0.0)
    throw SceneError(spec.source +
                     ": gradcheck of dynamic rigid scenes is not implemented (static scenes only)");
  if (!spec.fem_bodies.empty())
    throw SceneError(spec.source +
                     ": gradcheck of scenes with FEM bodies is not implemented (rigid bodies only)");
  if (spec.has_torques() || spec.stiffness.adaptive)
    throw SceneError(spec.source +
                     ": gradcheck needs a fixed contact stiffness and no torques (both are updated between "
                     "solves, the adjoint differentiates one solve)");
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
  StaticFunctional functional(*scene.model, identity_map(system.num_bodies()), objective,
                              scene.model->elimination().restrict_state(system.initial_state()), options);
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
  write_report_file((std::filesystem::path(out_dir) / "gradcheck.json").string(), document);
  return result;
}

}  // namespace tailor
