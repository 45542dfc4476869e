#pragma once
// The "rods" scene section (docs/rods.md, "Scene keys"): rods parsed once into typed specs,
// assembled into one Model (all rods' positions, then all twists), solved by Newton in load
// steps (reference frames updated between steps), and written as .vtu polylines.
#include <iosfwd>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "forward/rods/rod_parameters.hpp"
#include "forward/rods/rod_supports.hpp"

namespace tailor {

struct RodPointLoad {
  int vertex;
  Eigen::Vector3d force;
};

struct RodSpec {
  std::string name;
  Eigen::MatrixX3d points;
  RodMaterial material;
  double density = 0.0;  // [mass / length^3]
  std::vector<RodEnd> clamped;
  std::vector<int> pinned;
  std::vector<RodPointLoad> point_loads;
  std::vector<std::pair<int, double>> twisting_moments;  // (edge, moment)
};

struct RodSceneSpec {
  std::vector<RodSpec> rods;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  int load_steps = 1;
  int max_newton_iterations = 200;
};

// True when the JSON file has a top-level "rods" section.
bool is_rod_scene(const std::string& path);
// Throws std::invalid_argument naming the offending key on bad input.
RodSceneSpec parse_rod_scene(const nlohmann::json& scene);

struct RodSimulation {
  bool converged = false;
  int newton_iterations = 0;
  Vector state;
  std::string vtu_path;
};

// Solves the scene's equilibrium and writes out_dir/rods.vtu.
RodSimulation simulate_rods(const RodSceneSpec& spec, const std::string& out_dir,
                            std::ostream* log = nullptr);
// `tailor simulate` for a rod scene file; returns true when Newton converged at every step.
bool simulate_rod_scene_file(const std::string& path, const std::string& out_dir, std::ostream& log);

}  // namespace tailor
