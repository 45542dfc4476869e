// Torus chain scenes: parsing and `tailor simulate` (see torus_scene.hpp).
#include "problems/contact/torus_scene.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "adjoint/parameterization.hpp"
#include "adjoint/scaled_gradient.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/core/elimination.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/mesh_intersections.hpp"
#include "objectives/target_positions.hpp"
#include "problems/contact/surface_vtu.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_node.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {

TorusSceneSpec parse_torus_scene(const SceneNode& root) {
  root.expect_keys({"name", "description", "tori"});
  TorusSceneSpec spec;
  spec.source = root.source();
  if (root.has("name")) spec.name = root.at("name").string();
  if (root.has("description")) spec.description = root.at("description").string();
  const SceneNode t = root.at("tori");
  t.expect_keys({"count",
                 "major_radius",
                 "minor_radius",
                 "minor_radius_1",
                 "spacing",
                 "gap",
                 "density",
                 "tilt",
                 "fix_first",
                 "segments",
                 "contact_model",
                 "activation_distance",
                 "stiffness",
                 "min_stiffness",
                 "max_stiffness",
                 "friction",
                 "friction_velocity",
                 "pair_band",
                 "gravity",
                 "mode",
                 "time_step",
                 "steps",
                 "output_every",
                 "static_time_step",
                 "static_tolerance",
                 "max_static_steps",
                 "check_intersections",
                 "direction_tolerance",
                 "newton_iterations",
                 "gradcheck"});
  tori::ChainSpec& c = spec.chain;
  c.count = t.at("count").integer(2);
  if (c.count > 1000) t.at("count").fail("at most 1000 links");
  c.shape.major_radius = t.at("major_radius").positive();
  c.shape.minor_radius = t.at("minor_radius").positive();
  if (!(c.shape.minor_radius < c.shape.major_radius))
    t.at("minor_radius").fail("must be smaller than major_radius");
  // An elliptic tube (torus.hpp); equal to minor_radius it is the circular one (r1 follows r).
  if (t.has("minor_radius_1")) {
    const double r1 = t.at("minor_radius_1").positive();
    if (r1 != c.shape.minor_radius) c.shape.minor_radius_1 = r1;
  }
  if (t.has("spacing")) c.spacing = t.at("spacing").positive();
  if (t.has("gap")) c.gap = t.at("gap").positive();
  if (t.has("density")) c.density = t.at("density").positive();
  if (t.has("tilt")) c.tilt = t.at("tilt").number();
  if (!(std::abs(c.tilt) < M_PI)) t.at("tilt").fail("expected |tilt| < pi");
  if (t.has("fix_first")) c.fix_first = t.at("fix_first").boolean();
  if (t.has("segments")) {
    const std::vector<int> s = t.at("segments").integers(3);
    if (s.size() != 2) t.at("segments").fail("expected [major, minor] segment counts");
    c.major_segments = s[0];
    c.minor_segments = s[1];
  }
  const double s = c.effective_spacing(), R = c.shape.major_radius, r = c.shape.minor_radius;
  if (!(s > R && s < 2.0 * (R - r)))
    (t.has("spacing") ? t.at("spacing") : t.at("count"))
        .fail("links are interlocked and apart for major_radius < spacing < 2 (major_radius - minor_radius)");
  tori::ChainSimulationOptions& o = spec.options;
  if (t.has("contact_model"))
    o.model = t.at("contact_model").choice({"implicit", "mesh"}) == "mesh" ? tori::ContactModel::mesh
                                                                           : tori::ContactModel::implicit;
  if (t.has("activation_distance")) o.activation_distance = t.at("activation_distance").positive();
  // stiffness: a number fixes kappa; "adaptive" or absent: IPC's adaptive kappa
  // (chain_simulation.hpp), from min_stiffness (default: one pair at d_hat / 2 carries the free
  // links' weight) up to max_stiffness (default 100 min_stiffness).
  o.stiffness_control.adaptive = true;
  if (auto k = t.find("stiffness")) {
    if (k->is_string()) {
      if (k->string() != "adaptive")
        k->fail("expected a positive number (a fixed kappa) or \"adaptive\", got \"" + k->string() + "\"");
    } else {
      o.stiffness = k->positive();
      o.stiffness_control.adaptive = false;
    }
  }
  for (const char* key : {"min_stiffness", "max_stiffness"})
    if (t.has(key) && !o.stiffness_control.adaptive)
      t.at(key).fail(
          "only with adaptive stiffness (\"stiffness\": \"adaptive\" or absent; a number fixes kappa)");
  if (auto v = t.find("min_stiffness")) o.stiffness_control.min_stiffness = v->positive();
  if (auto v = t.find("max_stiffness")) o.stiffness_control.max_stiffness = v->positive();
  if (o.stiffness_control.min_stiffness > 0.0 && o.stiffness_control.max_stiffness > 0.0 &&
      o.stiffness_control.max_stiffness < o.stiffness_control.min_stiffness)
    t.at("max_stiffness").fail("must be at least min_stiffness");
  if (t.has("pair_band")) o.pair_band = t.at("pair_band").integer(0);
  if (t.has("gravity")) o.gravity = t.at("gravity").vector(3);
  if (t.has("direction_tolerance")) o.direction_tolerance = t.at("direction_tolerance").positive();
  if (t.has("newton_iterations")) o.newton.max_iterations = t.at("newton_iterations").integer(1);
  if (t.has("check_intersections")) o.check_intersections = t.at("check_intersections").boolean();
  const std::string mode = t.has("mode") ? t.at("mode").choice({"static", "dynamic"}) : "static";
  spec.dynamic = mode == "dynamic";
  if (t.has("time_step")) o.time_step = t.at("time_step").positive();
  if (t.has("steps")) spec.steps = t.at("steps").integer(1);
  if (t.has("output_every")) spec.output_every = t.at("output_every").integer(1);
  if (t.has("static_time_step")) spec.static_time_step = t.at("static_time_step").positive();
  if (t.has("static_tolerance")) spec.static_tolerance = t.at("static_tolerance").positive();
  if (t.has("max_static_steps")) spec.max_static_steps = t.at("max_static_steps").integer(1);
  if (!spec.dynamic) o.time_step = spec.static_time_step;
  // friction: IPC's lagged friction coefficient mu between the links; friction_velocity: eps_v.
  if (auto f = t.find("friction")) {
    o.friction.coefficient = f->non_negative();
    if (o.friction.coefficient > 0.0 && !spec.dynamic)
      f->fail("friction needs \"mode\": \"dynamic\" (a static relaxation is frictionless)");
  }
  if (auto v = t.find("friction_velocity")) {
    if (!(o.friction.coefficient > 0.0)) v->fail("only with a positive \"friction\"");
    o.friction.velocity_threshold = v->positive();
  }
  if (t.has("gradcheck")) {
    const SceneNode g = t.at("gradcheck");
    g.expect_keys({"parameters"});
    const std::vector<SceneNode> names = g.at("parameters").items();
    if (names.empty())
      g.at("parameters").fail("expected a non-empty list of \"masses\", \"radii\", \"placements\"");
    spec.gradcheck_masses = spec.gradcheck_radii = spec.gradcheck_placements = false;
    for (const SceneNode& name : names) {
      const std::string kind = name.choice({"masses", "radii", "placements"});
      bool& selected = kind == "masses"  ? spec.gradcheck_masses
                       : kind == "radii" ? spec.gradcheck_radii
                                         : spec.gradcheck_placements;
      if (selected) name.fail("\"" + kind + "\" is listed twice");
      selected = true;
    }
    if (spec.gradcheck_placements && !c.fix_first)
      g.at("parameters").fail("\"placements\" needs a fixed link (fix_first)");
  }
  return spec;
}

namespace {

void write_frame(const tori::ChainSimulation& sim, const std::string& dir, const std::string& suffix) {
  const Vector& q = sim.state();
  for (int b = 0; b < sim.system().num_bodies(); ++b) {
    const rigid::RigidBody& body = sim.system().body(b);
    const Eigen::Matrix3d Q = rigid::rotation_matrix(q.segment<3>(6 * b + 3));
    const Eigen::MatrixX3d x = (body.vertices * Q.transpose()).rowwise() + q.segment<3>(6 * b).transpose();
    write_surface_vtu((std::filesystem::path(dir) / (body.name + suffix + ".vtu")).string(), x, body.faces);
  }
}

std::string frame_suffix(int frame) {
  std::ostringstream s;
  s << "_" << std::setw(4) << std::setfill('0') << frame;
  return s.str();
}

double finite_or(double v, double fallback) { return std::isfinite(v) ? v : fallback; }

// A static relaxation needs a fixed link: links in contact resist only relative motion, so a
// chain without one moves as one rigid body under any load and never comes to rest.
void require_fixed_link(const TorusSceneSpec& spec) {
  if (spec.dynamic || spec.chain.fix_first) return;
  throw SceneError(spec.source +
                   ": tori.fix_first: no link is fixed, so the chain is free to move as one rigid body (3 "
                   "translations and 3 rotations; contact resists only relative motion) and a static "
                   "relaxation has no equilibrium to come to; fix the first link (\"fix_first\": true) or "
                   "use \"mode\": \"dynamic\"");
}

}  // namespace

TorusSimulateRun simulate_torus_scene(const TorusSceneSpec& spec, const std::string& out_dir,
                                      std::ostream* log) {
  require_fixed_link(spec);
  std::filesystem::create_directories(out_dir);
  tori::ChainSimulation sim(spec.chain, spec.options);
  TorusSimulateRun run;
  run.min_distance = std::numeric_limits<double>::infinity();
  nlohmann::json steps = nlohmann::json::array();
  auto record_step = [&](int n, const tori::ChainStepRecord& r) {
    steps.push_back({{"step", n},
                     {"converged", r.converged},
                     {"newton_iterations", r.newton_iterations},
                     {"seconds", r.seconds},
                     {"ccd_seconds", r.ccd_seconds},
                     {"min_distance", finite_or(r.min_distance, -1.0)},
                     {"active_pairs", r.active_pairs},
                     {"intersections", r.intersections},
                     {"stiffness", r.stiffness},
                     {"friction_sliding", r.sliding},
                     {"friction_sticking", r.sticking}});
    run.intersections += std::max(0, r.intersections);
    run.min_distance = std::min(run.min_distance, r.min_distance);
    ++run.steps;
    if (log)
      *log << "step " << n << ": " << (r.converged ? "converged" : "FAILED") << ", " << r.newton_iterations
           << " Newton iterations, min distance " << r.min_distance << ", " << r.active_pairs
           << " active pairs, " << r.intersections << " intersections, kappa " << r.stiffness
           << (spec.options.friction.coefficient > 0.0
                   ? ", friction pairs " + std::to_string(r.sliding) + " sliding / " +
                         std::to_string(r.sticking) + " sticking"
                   : std::string())
           << "\n";
  };
  const bool implicit = spec.options.model == tori::ContactModel::implicit;
  if (log)
    *log << "torus chain: " << spec.chain.count << " links, " << (implicit ? "implicit" : "mesh")
         << " contact, d_hat " << sim.activation_distance() << ", kappa " << sim.stiffness()
         << (spec.options.stiffness_control.adaptive ? " (adaptive)" : "") << ", friction "
         << spec.options.friction.coefficient << "\n";
  write_frame(sim, out_dir, frame_suffix(0));
  if (spec.dynamic) {
    run.converged = true;
    for (int n = 1; n <= spec.steps; ++n) {
      const tori::ChainStepRecord r = sim.step();
      record_step(n, r);
      if (!r.converged) {
        run.converged = false;
        if (log) *log << "step " << n << " failed: " << sim.last_message() << "\n";
        break;
      }
      if (n % spec.output_every == 0) write_frame(sim, out_dir, frame_suffix(n / spec.output_every));
    }
  } else {
    std::vector<tori::ChainStepRecord> records;
    const double tolerance =
        spec.static_tolerance > 0.0 ? spec.static_tolerance : 1e-10 * spec.chain.shape.major_radius;
    run.converged = sim.relax(tolerance, spec.max_static_steps, &records);
    for (std::size_t n = 0; n < records.size(); ++n) record_step(static_cast<int>(n) + 1, records[n]);
    if (!run.converged && log)
      *log << "no rest within " << spec.max_static_steps << " steps: " << sim.last_message() << "\n";
    write_frame(sim, out_dir, frame_suffix(1));
  }
  nlohmann::json links = nlohmann::json::array();
  const Vector& q = sim.state();
  for (int b = 0; b < sim.system().num_bodies(); ++b)
    links.push_back({{"name", sim.system().body(b).name},
                     {"position", {q[6 * b], q[6 * b + 1], q[6 * b + 2]}},
                     {"rotation", {q[6 * b + 3], q[6 * b + 4], q[6 * b + 5]}},
                     {"mass", sim.system().body(b).mass}});
  nlohmann::json pairs = nlohmann::json::array();
  if (sim.implicit_term())
    for (const tori::TorusPairForce& f : sim.implicit_term()->pair_forces(q, Vector()))
      pairs.push_back({{"a", f.a},
                       {"b", f.b},
                       {"distance", f.distance},
                       {"force_on_b", {f.force_on_b.x(), f.force_on_b.y(), f.force_on_b.z()}}});
  nlohmann::json report = {{"scene", spec.name},
                           {"contact_model", implicit ? "implicit" : "mesh"},
                           {"mode", spec.dynamic ? "dynamic" : "static"},
                           {"links", spec.chain.count},
                           {"activation_distance", sim.activation_distance()},
                           {"stiffness", sim.stiffness()},
                           {"initial_stiffness", sim.initial_stiffness()},
                           {"adaptive_stiffness", spec.options.stiffness_control.adaptive},
                           {"friction",
                            {{"coefficient", spec.options.friction.coefficient},
                             {"velocity_threshold", spec.options.friction.velocity_threshold}}},
                           {"converged", run.converged},
                           {"steps", run.steps},
                           {"intersections", run.intersections},
                           {"min_distance", finite_or(run.min_distance, -1.0)},
                           {"per_step", steps},
                           {"bodies", links},
                           {"pairs", pairs}};
  write_report(out_dir, report);
  if (log)
    *log << (run.completed() ? "completed" : "NOT completed") << ": " << run.steps << " steps, "
         << run.intersections << " intersections, min distance " << run.min_distance << "\n";
  return run;
}

TorusGradcheckRun gradcheck_torus_scene(const TorusSceneSpec& spec, const std::string& out_dir,
                                        const TorusGradcheckOptions& options, std::ostream* log) {
  if (spec.dynamic)
    throw SceneError(spec.source +
                     ": tori.mode: gradcheck differentiates the static equilibrium (\"mode\": "
                     "\"static\"); the adjoint of torus dynamics is not implemented");
  if (spec.options.model != tori::ContactModel::implicit)
    throw SceneError(spec.source +
                     ": tori.contact_model: gradcheck needs the implicit model (the mesh "
                     "model has no radius parameters)");
  require_fixed_link(spec);
  // The equilibrium by relaxation, as in `simulate`.
  tori::ChainSimulationOptions sim_options = spec.options;
  sim_options.time_step = spec.static_time_step;
  tori::ChainSimulation sim(spec.chain, sim_options);
  const double tolerance =
      spec.static_tolerance > 0.0 ? spec.static_tolerance : 1e-10 * spec.chain.shape.major_radius;
  if (!sim.relax(tolerance, spec.max_static_steps))
    throw SceneError(spec.source + ": the chain did not come to rest within tori.max_static_steps (" +
                     std::to_string(spec.max_static_steps) + "): " + sim.last_message());
  const rigid::RigidBodySystem& system = sim.system();
  const Vector equilibrium = sim.state();
  const int n = system.num_bodies();

  TorusGradcheckRun run;
  run.intersections = tori::count_body_intersections(system, equilibrium);
  run.active_pairs = sim.active_pairs();
  run.min_distance = sim.min_distance(sim.activation_distance());

  std::vector<int> anchors;  // the fixed links, in body order (their placements' order in p)
  for (int b = 0; b < n; ++b)
    if (system.body(b).fixed) anchors.push_back(b);
  if (spec.gradcheck_placements && anchors.empty())
    throw SceneError(spec.source + ": tori.gradcheck.parameters: \"placements\" needs a fixed link");
  const int num_placements = 6 * static_cast<int>(anchors.size());
  Model model(system.num_dofs());
  model.parameter_layout().add("masses", n);
  model.parameter_layout().add("torus_radii", 2 * n);
  model.parameter_layout().add("torus_placements", num_placements);
  model.add(std::make_unique<rigid::RigidGravityTerm>(system, spec.options.gravity, 0));
  tori::TorusContactOptions contact;
  contact.activation_distance = sim.activation_distance();
  contact.stiffness = sim.stiffness();
  contact.pair_band = spec.options.pair_band;
  contact.parameter_offset = n;
  // The fixed links' poses from p (their placements) only when they are designed: otherwise
  // the contact term reads them from the held DOFs, as before placements were parameters.
  if (spec.gradcheck_placements) contact.placement_offset = 3 * n;
  model.add(std::make_unique<tori::TorusContactTerm>(system, sim.shapes(), contact));
  std::vector<int> fixed = system.fixed_dofs();
  std::vector<int> centres;
  double weight = 0.0;
  for (int b = 0; b < n; ++b)
    if (!system.body(b).fixed) {
      fixed.push_back(6 * b + 5);
      centres.push_back(2 * b);  // block 2b of 3 DOFs is T_b
      weight += system.body(b).mass * spec.options.gravity.norm();
    }
  if (centres.empty())
    throw SceneError(spec.source + ": gradcheck needs at least one link that is not fixed");
  model.set_elimination(Elimination::dirichlet(fixed, equilibrium));
  Matrix targets(static_cast<Eigen::Index>(centres.size()), 3);
  for (std::size_t i = 0; i < centres.size(); ++i)
    targets.row(static_cast<Eigen::Index>(i)) = system.initial_state().segment<3>(3 * centres[i]).transpose();
  auto objective = std::make_shared<TargetPositions>(3, centres, targets);
  StaticFunctionalOptions functional_options;
  functional_options.newton = spec.options.newton;
  // The barrier's round-off floor (docs/tori.md): an absolute residual of 1e-7 of the weight.
  functional_options.newton.absolute_tolerance = 1e-7 * weight;
  // p = (masses, radii, placements) at the scene's values; z the selected blocks, the rest held.
  Vector p(3 * n + num_placements);
  for (int b = 0; b < n; ++b) {
    p[b] = system.body(b).mass;
    p[n + 2 * b] = sim.shapes()[static_cast<std::size_t>(b)].major_radius;
    p[n + 2 * b + 1] = sim.shapes()[static_cast<std::size_t>(b)].minor_radius;
  }
  for (std::size_t k = 0; k < anchors.size(); ++k)
    p.segment<6>(3 * n + 6 * static_cast<int>(k)) = equilibrium.segment<6>(6 * anchors[k]);
  std::vector<ParameterBlock> blocks;
  std::vector<Vector> design;
  auto select = [&](bool selected, int offset, int size) {
    if (!selected) return;
    blocks.push_back({offset, identity_map(size)});
    design.push_back(p.segment(offset, size));
  };
  select(spec.gradcheck_masses, 0, n);
  select(spec.gradcheck_radii, n, 2 * n);
  select(spec.gradcheck_placements, 3 * n, num_placements);
  Vector z(0);
  for (const Vector& d : design) {
    z.conservativeResize(z.size() + d.size());
    z.tail(d.size()) = d;
  }
  StaticFunctional functional(model, embed_blocks(p, blocks), objective,
                              model.elimination().restrict_state(equilibrium), functional_options);
  ScaledGradient scaled(functional, options.gradient_scale);
  TaylorTestOptions taylor;
  taylor.seed = options.seed;
  taylor.initial_step = options.initial_step;
  // The direction's entries are u_i max(|z_i|, floor): a placement's zero coordinates would get
  // the default floor 1e-2; with placements the floor is R (lengths in units of the link size,
  // angles of order one radian).
  if (spec.gradcheck_placements) taylor.direction_floor = spec.chain.shape.major_radius;
  run.taylor = taylor_test(scaled, z, taylor);
  std::string described;
  auto describe = [&](bool selected, const std::string& what) {
    if (!selected) return;
    described += (described.empty() ? "" : ", then ") + what;
  };
  describe(spec.gradcheck_masses, "the masses m_0..m_{n-1}");
  describe(spec.gradcheck_radii, std::string("the radii (R_i, r_i) per link") +
                                     (tori::is_elliptic(spec.chain.shape) ? " (minor_radius_1 held)" : ""));
  describe(spec.gradcheck_placements, "the placement (T, w) of each fixed link");
  if (log)
    *log << "torus chain at rest: " << run.active_pairs << " active pairs, min distance " << run.min_distance
         << ", " << run.intersections << " intersections\n"
         << "gradient of 1/2 sum |T_b - T_b^0|^2 with respect to " << described << "\n"
         << run.taylor.table();
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json document = taylor_json(run.taylor);
  add_report_header(document);
  document["scene"] = {{"name", spec.name}, {"source", spec.source}};
  document["parameters"] = described;
  document["active_pairs"] = run.active_pairs;
  document["min_distance"] = run.min_distance;
  document["intersections"] = run.intersections;
  write_report_file((std::filesystem::path(out_dir) / "gradcheck.json").string(), document);
  return run;
}

}  // namespace tailor
