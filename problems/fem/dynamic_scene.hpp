#pragma once
// Dynamic scenes: the optional "dynamics" section of a scene turns `tailor simulate` into a
// time integration (forward/dynamics) of the scene's static model plus inertia and Rayleigh
// damping. Loads (gravity included) act from t = 0 as dead loads, prescribed displacements are
// applied from t = 0, and the body starts at rest positions with the given initial velocity.
// With an "objective" in the section, `tailor gradcheck` Taylor-tests its gradient.
//
// The dynamic path is split like the static one: this header holds the section as typed data
// (parsed by parse_dynamics_section, dynamic_scene.cpp) and the model built from it
// (build_dynamic_scene, dynamic_model.cpp); the verbs are in problems/fem/dynamic_commands.hpp and
// the files they write in problems/fem/dynamic_report.hpp.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "forward/dynamics/descent_solver.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/dynamics/time_integrator.hpp"
#include "forward/fem/mass.hpp"
#include "objectives/trajectory_objective.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/static_scene.hpp"

namespace tailor {

// The trajectory objective of `tailor gradcheck` on a dynamic scene: the selected vertices'
// positions (rest position + `target`) or velocities (`target`) at the listed steps.
struct TrajectoryTargetSpec {
  VertexSelector vertices;
  TrajectoryQuantity quantity = TrajectoryQuantity::position;
  std::vector<int> steps;  // empty: the last step
  Eigen::VectorXd target;
  std::string key = "dynamics.objective";
};

// dynamics.reduction.domains: the domains of a "domains" or "overlapping" basis.
struct DynamicDomainsSpec {
  int count = 4;                      // METIS domains
  bool from_regions = false;          // or the mesh's element regions
  int fixed_interface_modes = 6;      // "domains": per domain
  int derivative_modes = 3;           // "domains": local derivatives of this many fixed-interface modes
  int boundary_derivative_modes = 2;  // "domains": local derivatives of this many boundary-driven modes
  int interface_modes = 12;           // "domains": interface excitations (0 = every interface DOF)
  int overlap_layers = 2;             // "overlapping": element rings grown around each domain
};

// dynamics.reduction: the steps run in reduced coordinates, u = Phi q (forward/reduction;
// problems/fem/reduced_dynamic_run.hpp; docs/reduction.md, "Reduced dynamic scenes").
struct DynamicReductionSpec {
  std::string basis = "global";  // "global", "domains" or "overlapping"
  int displacement_modes = 10;   // global: lowest vibration modes
  bool static_responses = true;  // global: K^-1 f of the loads (gravity included)
  int derivative_modes = 3;      // global: modes (with the load response) whose Krylov blocks 2..k are added
  int krylov_order = 2;          // 1: none; 2: modal derivatives; up to 4 (nonlinear materials only)
  std::string energy = "auto";   // "polynomial" (StVK, linear), "projected" (any material) or "auto"
  std::string rotations = "none";            // "domains": the basis turns with each domain (Newmark, projected)
  std::string rotation_blend = "quaternion";  // with rotations: "quaternion", "nearest" or "linear"
  DynamicDomainsSpec domains;
  std::string key = "dynamics.reduction";
};

struct DynamicsSpec {
  TimeScheme scheme = TimeScheme::implicit_euler;
  double time_step = 0.01;  // h [time]
  int steps = 100;
  MassLumping lumping = MassLumping::consistent;
  double rayleigh_alpha = 0.0;                      // [1/time]
  double rayleigh_beta = 0.0;                       // [time]; K is the rest stiffness
  int output_every = 1;                             // write a frame every this many steps (and the last)
  std::optional<Eigen::VectorXd> initial_velocity;  // uniform, one entry per dimension
  std::optional<TrajectoryTargetSpec> objective;    // for `tailor gradcheck`
  // dynamics.solver: "newton" (default; the scene's "solver" section) or "descent" with its
  // options (forward/dynamics/descent_solver.hpp; docs/dynamics.md, "The descent solver").
  std::string solver_method = "newton";
  DescentOptions descent;
  std::optional<DynamicReductionSpec> reduction;  // dynamics.reduction: reduced steps
};

// The model of a dynamic scene: the static scene's model plus inertia and Rayleigh damping,
// its parameters p (Young's moduli, Poisson's ratios, densities, alpha and beta), and the
// initial state.
struct DynamicSceneModel {
  StaticSetup setup;
  std::unique_ptr<Model> model;
  DynamicTerms terms;
  Vector p, rest, initial_positions, initial_velocities;
  TimeIntegratorOptions options;
  bool rayleigh = false;
};

// Throws SceneError for scene problems (a material without a positive density, an initial
// velocity of the wrong size) and what setup_static_scene throws.
DynamicSceneModel build_dynamic_scene(const Scene& scene);

}  // namespace tailor
