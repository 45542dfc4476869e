// The "dynamics" section of a scene as typed data (declared in problems/fem/scene_parsing.hpp).
#include "problems/fem/dynamic_scene.hpp"

#include "problems/fem/scene_parsing.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

// dynamics.reduction (docs/reduction.md, "Reduced dynamic scenes").
DynamicReductionSpec parse_dynamic_reduction(const SceneNode& node) {
  node.expect_keys({"basis", "displacement_modes", "static_responses", "derivative_modes", "krylov_order", "energy",
                    "domains", "rotations", "rotation_blend"});
  DynamicReductionSpec r;
  r.key = node.path();
  if (auto k = node.find("basis")) r.basis = k->choice({"global", "domains", "overlapping"});
  if (auto k = node.find("displacement_modes")) r.displacement_modes = k->integer(1);
  if (auto k = node.find("static_responses")) r.static_responses = k->boolean();
  if (auto k = node.find("derivative_modes")) r.derivative_modes = k->integer(0);
  if (auto k = node.find("krylov_order")) r.krylov_order = k->integer(1);
  if (r.krylov_order > 4) node.at("krylov_order").fail("at most 4 (the block sizes grow as C(r + k - 1, k))");
  if (r.basis == "domains")
    for (const char* key : {"displacement_modes", "static_responses", "derivative_modes", "krylov_order"})
      if (node.find(key))
        node.at(key).fail("applies to the \"global\" and \"overlapping\" bases (\"domains\" takes its modes "
                          "from the \"domains\" keys)");
  if (auto k = node.find("energy")) r.energy = k->choice({"auto", "polynomial", "projected"});
  if (auto k = node.find("rotations")) {
    r.rotations = k->choice({"none", "domains"});
    if (r.rotations == "domains" && r.basis == "global")
      k->fail("\"domains\" needs \"basis\": \"domains\" or \"overlapping\" (a global basis has no domains to turn)");
    if (r.rotations == "domains" && r.energy == "polynomial")
      k->fail("a turning basis has no precomputed polynomial: \"energy\" must be \"auto\" or \"projected\"");
  }
  if (auto k = node.find("rotation_blend")) {
    if (r.rotations != "domains") k->fail("only with \"rotations\": \"domains\"");
    r.rotation_blend = k->choice({"quaternion", "nearest", "linear"});
  }
  if (auto k = node.find("domains")) {
    if (r.basis == "global") k->fail("only with \"basis\": \"domains\" or \"overlapping\"");
    k->expect_keys({"count", "from_regions", "fixed_interface_modes", "derivative_modes",
                    "boundary_derivative_modes", "interface_modes", "overlap_layers"});
    DynamicDomainsSpec& d = r.domains;
    if (auto e = k->find("count")) d.count = e->integer(1);
    if (auto e = k->find("from_regions")) d.from_regions = e->boolean();
    if (auto e = k->find("overlap_layers")) d.overlap_layers = e->integer(0);
    for (const char* key : {"fixed_interface_modes", "derivative_modes", "boundary_derivative_modes", "interface_modes",
                            "overlap_layers"}) {
      const bool layers = std::string(key) == "overlap_layers";
      const bool applies = r.basis == "domains" ? !layers : layers;
      if (!applies && k->find(key))
        k->at(key).fail(std::string("does not apply to \"basis\": \"") + r.basis + "\"");
    }
    if (auto e = k->find("fixed_interface_modes")) d.fixed_interface_modes = e->integer(0);
    if (auto e = k->find("derivative_modes")) d.derivative_modes = e->integer(0);
    if (auto e = k->find("boundary_derivative_modes")) d.boundary_derivative_modes = e->integer(0);
    if (auto e = k->find("interface_modes")) d.interface_modes = e->integer(0);
  }
  return r;
}

}  // namespace

DynamicsSpec parse_dynamics_section(const SceneNode& node, const std::string& directory) {
  node.expect_keys({"scheme", "time_step", "steps", "mass", "rayleigh", "output_every", "initial_velocity", "objective",
                    "solver", "reduction"});
  DynamicsSpec d;
  if (auto v = node.find("scheme"))
    d.scheme = parse_time_scheme(v->choice({"implicit_euler", "newmark", "bdf2"}));
  d.time_step = node.at("time_step").positive();
  d.steps = node.at("steps").integer(1);
  if (auto v = node.find("mass"))
    d.lumping =
        v->choice({"consistent", "lumped"}) == "lumped" ? MassLumping::lumped : MassLumping::consistent;
  if (auto r = node.find("rayleigh")) {
    r->expect_keys({"alpha", "beta"});
    if (auto a = r->find("alpha")) d.rayleigh_alpha = a->non_negative();
    if (auto b = r->find("beta")) d.rayleigh_beta = b->non_negative();
  }
  if (auto v = node.find("output_every")) d.output_every = v->integer(1);
  if (auto v = node.find("initial_velocity")) d.initial_velocity = v->vector();
  if (auto o = node.find("objective")) {
    o->expect_keys({"vertices", "quantity", "steps", "target"});
    TrajectoryTargetSpec t;
    t.key = o->path();
    t.vertices = parse_vertex_selector(o->at("vertices"), directory);
    if (auto q = o->find("quantity"))
      t.quantity = q->choice({"position", "velocity"}) == "velocity" ? TrajectoryQuantity::velocity
                                                                     : TrajectoryQuantity::position;
    if (auto steps = o->find("steps")) {
      t.steps = steps->integers(1);
      for (int step : t.steps)
        if (step > d.steps)
          steps->fail("step " + std::to_string(step) + " is beyond the last step " + std::to_string(d.steps));
    }
    t.target = o->at("target").vector();
    d.objective = t;
  }
  if (auto solver = node.find("solver")) {
    solver->expect_keys({"method", "max_iterations", "relative_tolerance", "step_length", "rho",
                         "rho_estimation_iterations", "device", "preconditioner"});
    if (auto v = solver->find("method")) d.solver_method = v->choice({"newton", "descent"});
    for (const char* key : {"max_iterations", "relative_tolerance", "step_length", "rho", "rho_estimation_iterations",
                            "device", "preconditioner"})
      if (d.solver_method != "descent" && solver->find(key))
        solver->at(key).fail("applies to \"method\": \"descent\" only (Newton's settings are in the scene's "
                             "\"solver\" section)");
    if (auto v = solver->find("max_iterations")) d.descent.max_iterations = v->integer(1);
    if (auto v = solver->find("relative_tolerance")) d.descent.relative_tolerance = v->open_interval(0.0, 1.0);
    if (auto v = solver->find("step_length")) d.descent.step_length = v->positive();
    if (auto v = solver->find("rho")) {
      const double rho = v->number();
      if (!(rho >= 0.0 && rho < 1.0)) v->fail("expected a number in [0, 1) (0: no acceleration)");
      d.descent.rho = rho;
    }
    if (auto v = solver->find("rho_estimation_iterations")) d.descent.rho_estimation_iterations = v->integer(2);
    // Where the descent passes run (docs/dynamics.md, "The GPU path"); "gpu" without a device is
    // an error when the solver is made.
    if (auto v = solver->find("device")) {
      const std::string device = v->choice({"cpu", "gpu", "auto"});
      d.descent.device = device == "gpu"    ? DescentDevice::gpu
                         : device == "auto" ? DescentDevice::automatic
                                            : DescentDevice::cpu;
    }
    if (auto v = solver->find("preconditioner"))
      d.descent.preconditioner = v->choice({"projected_hessian", "vertex_blocks"}) == "vertex_blocks"
                                     ? DescentPreconditioner::vertex_blocks
                                     : DescentPreconditioner::projected_hessian;
  }
  if (auto r = node.find("reduction")) d.reduction = parse_dynamic_reduction(*r);
  return d;
}

}  // namespace tailor
