#pragma once
// The studio's interactive material design: a handle scene's reduced design loop
// (problems/fem/reduced_design.hpp, Xu et al. 2015) held in memory, retargeted by
// set_handle_targets and designed again from the last design on every drag, with what the page
// draws (the boundary surface, the handles) extracted once.
//
// Units are the scene's. Positions and displacements are per vertex (x, y, z rows); Young's
// modulus is per element, shown per surface triangle (the modulus of the tet it bounds).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "problems/fem/reduced_design.hpp"

namespace tailor::studio {

// The boundary of the tet mesh as the page draws it.
struct SurfaceMesh {
  std::vector<int> vertices;   // mesh vertex of each surface vertex
  Eigen::MatrixXi triangles;   // num_triangles x 3, indices into `vertices`, outward normals
  Eigen::VectorXi owners;      // the element each triangle bounds
};
SurfaceMesh extract_surface(const Mesh& mesh);

struct DesignState {
  Vector w;                             // material-mode weights
  Eigen::VectorXd youngs_modulus;       // per element
  Vector displacement;                  // num_dofs, the reduced equilibrium Phi q
  std::vector<double> reduced_errors;   // per handle, |mean u - ubar| / |ubar|
  int iterations = 0;
  double seconds = 0.0;                 // of the last design
  double optimizer_seconds = 0.0;       // of its optimization alone
  std::string status, message;         // the optimizer's
  int evaluations = 0;                  // reduced functional evaluations of the last design
  bool superseded = false;              // stopped because a newer request arrived
};

class DesignSession {
 public:
  static constexpr std::size_t kSettleWindow = 5;
  static constexpr double kSettleTolerance = 5e-4;

  // Builds the reduced design (the precomputation: seconds for large meshes). Throws as
  // build_reduced_design does.
  explicit DesignSession(const Scene& scene);

  const ReducedDesign& design() const { return design_; }
  const SurfaceMesh& surface() const { return surface_; }
  const DesignState& state() const { return state_; }
  const std::vector<Eigen::VectorXd>& targets() const { return targets_; }
  Eigen::VectorXd handle_rest_centre(int handle) const;  // mean rest position of its vertices

  // Designs again for new targets from the last design, with the scene's optimizer, until it
  // stops or the design has settled: sqrt(2 J), the handles' relative error, fell by at most
  // kSettleTolerance (0.05% of the target displacement) over the last kSettleWindow iterations.
  // A drag needs the design the eye sees, not the scene's tolerance: along the smoothness
  // term's slow valley L-BFGS spends ~100 iterations taking the error from 0.7% to 0.2%
  // (scenes/cantilever_handle_reduced.json); save() converges as `tailor run`. `keep_going(iteration, objective)` is
  // asked after every optimizer iteration; false stops the design (superseded: the state keeps
  // the last finished design and its targets). Throws std::invalid_argument for bad targets
  // (count, size, zero, non-finite), leaving everything unchanged.
  const DesignState& redesign(const std::vector<Eigen::VectorXd>& targets,
                              const std::function<bool(int, double)>& keep_going);

  // The current design solved in full space (from the reduced solution).
  FullSpaceCheck check_full_space() const;

  // Runs the design for the current targets as `tailor run` does (report.json in `out_dir`),
  // and writes out_dir/result.vtu (youngs_modulus per cell, displacement per point, deformed).
  // Returns the report's path.
  std::string save(const std::string& out_dir);

 private:
  ReducedDesign design_;
  SurfaceMesh surface_;
  std::vector<Eigen::VectorXd> targets_;
  DesignState state_;
};

}  // namespace tailor::studio
