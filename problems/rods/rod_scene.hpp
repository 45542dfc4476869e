#pragma once
// The "rods" scene section (docs/rods.md, "Scene keys"): rods parsed once into typed specs,
// assembled into one Model (all rods' positions, then all twists), solved by Newton in load
// steps (reference frames updated between steps), and written as .vtu polylines.
#include <functional>
#include <iosfwd>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/rods/rigid_joint_term.hpp"
#include "forward/rods/rod_parameters.hpp"
#include "forward/rods/rod_supports.hpp"
#include "problems/fem/dynamic_scene.hpp"
#include "problems/rods/rod_vtu.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

class RodTwistingMomentTerm;

struct RodPointLoad {
  int vertex;
  Eigen::Vector3d force;
};

struct RodSpec {
  std::string name;
  Eigen::MatrixX3d points;
  RodMaterial material;
  double density = 0.0;        // [mass / length^3]
  bool closed = false;         // a ring: the last vertex joins the first
  double closing_twist = 0.0;  // closed rods: total twist imposed when the ends were joined [rad]
  bool straight_rest = false;  // rest curvatures and twists zero (naturally straight rod)
  // "ends": "edge_midpoints": the rod's ends are the midpoints of its first and last edges (a
  // line's from/to, loads at an "end" split over the end edge, the end edges' weight halved);
  // with a clamped end edge this is the staggered set-up, second order (docs/rods.md).
  bool ends_at_edge_midpoints = false;
  std::vector<RodEnd> clamped;
  std::vector<int> clamped_edges;  // both vertices and the twist of each edge held
  std::vector<int> pinned;
  std::vector<RodPointLoad> point_loads;
  std::vector<std::pair<int, double>> twisting_moments;  // (edge, moment)
};

// A joint: the listed (rod, vertex) pairs share one position (their position DOFs are tied in
// the elimination). Pinned: the rods' frames and twists stay independent (free rotation).
// Rigid: the joint also carries a rotation vector (three DOFs after all rods' twists), and every
// member edge at the joint (the end edge at an end vertex, both edges at an interior one) is
// coupled to the joint's frame by RodRigidJointTerm (forward/rods/rigid_joint_term.hpp).
struct RodJointSpec {
  std::vector<std::pair<int, int>> members;  // (rod index, vertex)
  bool rigid = false;
};

struct RodSceneSpec {
  std::vector<RodSpec> rods;
  std::vector<RodJointSpec> joints;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  int load_steps = 1;
  int max_newton_iterations = 200;
  // The "dynamics" section (docs/rods.md, "Dynamics"): time integration instead of load steps.
  std::optional<DynamicsSpec> dynamics;
  std::string source;  // the scene file, for reports (empty when parsed from memory)
};

// The scene's document (the "rods" section and the top-level keys of docs/rods.md). Throws
// SceneError "<source>: <key path>: <what>" on bad input, unknown keys included.
RodSceneSpec parse_rod_scene(const SceneNode& root);
// The same for a document without a file (tests, programs that build scenes in memory).
RodSceneSpec parse_rod_scene(const nlohmann::json& scene, const std::string& source = "rods scene");

// The rods' dead loads (gravity, point loads, twisting moments) scaled by a load factor:
// E = -factor f . x.
class RodLoadTerm final : public EnergyTerm {
 public:
  explicit RodLoadTerm(Vector forces) : forces_(std::move(forces)) {}
  std::string name() const override { return "rod_loads"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  const Vector& forces() const { return forces_; }  // at factor 1
  double factor = 1.0;

 private:
  Vector forces_;
};

// All rods of a scene in one Model: every rod's positions (rod k's vertex v is the global
// vertex first_vertex[k] + v, at x[prefix + 3 (first_vertex[k] + v) + c]), then every rod's twists; the
// three energy terms per rod, the supports eliminated, the loads at factor 1; p with the uniform
// material and the stress-free rest shape of every rod.
struct RodSceneModel {
  std::unique_ptr<Model> model;
  std::vector<std::shared_ptr<DiscreteRod>> rods;
  std::vector<RodParameterBlocks> blocks;
  std::vector<int> first_vertex;
  Vector p, rest;
  RodLoadTerm* load = nullptr;
  // One per rod with twisting moments (forward/rods/twisting_moment_term.hpp): their load
  // factor follows load->factor, their branches the frame updates.
  std::vector<RodTwistingMomentTerm*> twisting_moments;
  std::vector<RodRigidJointTerm*> rigid_joints;  // in the order of the rigid joints of the spec
  std::vector<RodOutput> outputs() const;
};
struct RodSimulation {
  bool converged = false;
  int newton_iterations = 0;
  Vector state;
  std::string vtu_path;
  std::string report_path;
};

// DOFs and parameters placed before the rods' in the model (the FEM part of a scene with rods
// and a mesh, problems/rods/rod_fem_scene.cpp): the rods' DOFs start at `dofs`, their parameter
// blocks after `parameter_blocks`; `fixed_dofs` (< dofs) are held at `values` (size dofs).
struct RodModelPrefix {
  int dofs = 0;
  std::vector<std::pair<std::string, int>> parameter_blocks;  // (name, size)
  std::vector<int> fixed_dofs;
  Vector values;
};
RodSceneModel build_rod_model(const RodSceneSpec& spec, const RodModelPrefix& prefix = {});
// The load steps, frame updates, rods.vtu and report.json of simulate_rods on a built model.
RodSimulation solve_rod_model(RodSceneModel& m, const RodSceneSpec& spec, const std::string& out_dir,
                              std::ostream* log = nullptr);

// Solves the scene's equilibrium and writes out_dir/rods.vtu and out_dir/report.json (status,
// energies by term, the final residual, Newton iterations per load step, threads).
RodSimulation simulate_rods(const RodSceneSpec& spec, const std::string& out_dir,
                            std::ostream* log = nullptr);

// ---- Dynamics -------------------------------------------------------------------------------
// The lumped diagonal mass of all rods of a scene model: each rod's vertex masses on its
// position DOFs and its edges' twist inertias rho (I1 + I2) L on its twist DOFs
// (add_rod_mass_diagonal, forward/rods/rod_supports.hpp), from each rod's density.
Vector rod_scene_mass_diagonal(const RodSceneSpec& spec, const RodSceneModel& m);
// Adds the InertiaTerm of a fixed diagonal mass to m.model (one per model).
InertiaTerm& add_rod_inertia(RodSceneModel& m, Vector diagonal);

struct RodDynamicsRun {
  bool completed = false;
  std::string message;  // why it stopped early
  int steps = 0, newton_iterations = 0;
  double seconds = 0.0;
  std::vector<double> time, kinetic_energy, potential_energy;  // at every step, step 0 included
  DynamicState state;                                          // the last one
  std::vector<std::string> frames;                             // .vtu files written
  std::string pvd_path, report_path;
};
using RodStepObserver = std::function<void(const DynamicState&)>;

// Integrates m (which holds an InertiaTerm, add_rod_inertia) in time with the scheme of
// `dynamics` from positions x0 and velocities v0 (full DOF space); the loads act from t = 0 at
// factor 1. After every step the rods' reference frames move to the new state (time-parallel
// transport; the material frames are unchanged by the update, so the state stays valid). With a
// non-empty out_dir: out_dir/frames/rods_<step>.vtu every output_every steps (and the last),
// out_dir/rods.pvd and out_dir/report.json. `observer` sees every state, step 0 included.
RodDynamicsRun integrate_rods(RodSceneModel& m, const DynamicsSpec& dynamics, const Vector& x0,
                              const Vector& v0, const std::string& out_dir, std::ostream* log = nullptr,
                              const RodStepObserver& observer = {});
// The scene's dynamics from rest positions with dynamics.initial_velocity on every vertex.
RodDynamicsRun simulate_rod_dynamics(const RodSceneSpec& spec, const std::string& out_dir,
                                     std::ostream* log = nullptr);
// A scene with a "rods" section and a "mesh" section: the FEM body (the static scene's keys:
// mesh, materials, dirichlet, loads, solver) and the rods in one Model, solved by one Newton
// solve (they do not interact). Writes out_dir/rods.vtu, out_dir/result.vtu (the body,
// deformed, with its displacement) and out_dir/report.json (energies by term of both).
// Throws SceneError for load steps > 1, a "dynamics" or "inverse" section.
struct RodFemSimulation {
  RodSimulation rods;  // .state: the whole state (FEM DOFs first)
  int fem_dofs = 0;
  std::string fem_vtu_path;
};
RodFemSimulation simulate_rods_with_fem(const SceneNode& root, const std::string& directory,
                                        const std::string& out_dir, std::ostream* log = nullptr);

// `tailor simulate` on a rod scene's document (`directory`: where a mesh file's path starts): the
// equilibrium, the dynamics, or the rods next to a mesh. True when every solve converged.
bool simulate_rod_scene(const SceneNode& root, const std::string& directory, const std::string& out_dir,
                        std::ostream* log);

}  // namespace tailor
