#pragma once
// Scenes of periodic interlocking cells (docs/interlocking.md, docs/scenes.md): an
// "interlocking" section with the cell, the boundary sweep and an optional limit design.
//   tailor simulate scene.json   the strain-space boundary: report.json, boundary.png, sample_<k>.vtu
//   tailor gradcheck scene.json  Taylor test of the limit design functional at the scene's design
//   tailor run scene.json        the limit design, then a fresh sweep of the designed cell
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "problems/interlocking/limit_design.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

struct InterlockingBoundarySpec {
  std::string loading = "principal";  // "principal" (eps_xx, eps_yy rays) or "uniaxial"
  int directions = 32;
  double shear = 0.0;  // a fixed eps_xy of every path (a mixed state)
  bool vtu = true;     // sample_<k>.vtu per direction
  // Periodic single curvature (curved_periodicity.hpp): each uniaxial direction t bends the
  // periodic cell to curvature s along t (the cylinder's screw-motion periodicity), s the curvature.
  bool single_curvature = false;
  interlocking::LimitOptions options;
  std::vector<interlocking::LoadPath> paths() const;
};

struct InterlockingDesignSpec {
  std::vector<DesignVariable> variables;
  std::vector<LimitTarget> targets;
  double margin = 0.02;   // non-penetration margin at the rest placement [length]
  double reach = 0.3;     // pairs within this at the start get a margin constraint [length]
  OptimizerOptions optimizer;
  TaylorTestOptions gradcheck;
};

struct InterlockingScene {
  std::string name;
  interlocking::RigidCellSpec cell;
  InterlockingBoundarySpec boundary;
  std::optional<InterlockingDesignSpec> design;
};

// Throws SceneError naming file and key path.
InterlockingScene parse_interlocking_scene(const SceneNode& root);

// The boundary of `cell`, written to out_dir (report.json, boundary.png, sample_<k>.vtu).
// Returns true when every path ended locked or free (none stalled) and every state was certified
// apart by the independent clearance check.
bool run_interlocking_boundary(const InterlockingScene& scene, const interlocking::RigidCellSpec& cell,
                               const std::string& out_dir, std::ostream* log);
// The Taylor test of the design functional (gradcheck.json).
bool gradcheck_interlocking_design(const InterlockingScene& scene, const std::string& out_dir, unsigned seed,
                                   std::ostream* log);
// The design, then the fresh sweep of the design in out_dir/designed (report.json has both).
bool run_interlocking_design(const InterlockingScene& scene, const std::string& out_dir, std::ostream* log,
                             std::ostream* progress);

}  // namespace tailor
