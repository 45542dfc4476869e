// The "dynamics" section of a scene as typed data (declared in problems/fem/scene_parsing.hpp).
#include "problems/fem/dynamic_scene.hpp"

#include "problems/fem/scene_parsing.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

DynamicsSpec parse_dynamics_section(const SceneNode& node, const std::string& directory) {
  node.expect_keys({"scheme", "time_step", "steps", "mass", "rayleigh", "output_every", "initial_velocity", "objective",
                    "solver"});
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
                         "rho_estimation_iterations"});
    if (auto v = solver->find("method")) d.solver_method = v->choice({"newton", "descent"});
    for (const char* key : {"max_iterations", "relative_tolerance", "step_length", "rho", "rho_estimation_iterations"})
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
  }
  return d;
}

}  // namespace tailor
