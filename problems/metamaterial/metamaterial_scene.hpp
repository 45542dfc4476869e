#pragma once
// `tailor run cell.json` for a periodic-cell scene with a "design" section: density-based
// design of the cell (cell_design.hpp) with a volume constraint through the optimizer
// interface, then the physical re-checks: the design thresholded at rho = 1/2 on the design
// mesh and on a refined mesh (grid cells). Keys and report in docs/homogenization.md.
#include <iosfwd>
#include <string>

#include "optimizers/optimizer.hpp"
#include "problems/homogenization/cell_scene.hpp"
#include "problems/metamaterial/cell_design.hpp"

namespace tailor {

// The largest refined check (design mesh elements times refine^dim) a scene may ask for.
inline constexpr double kMaxRefinedElements = 2e6;

struct MetamaterialDesignSpec {
  SimpMaterial material;
  double filter_radius = 0.0;  // minimum length scale
  double max_volume_fraction = 0.5;
  std::vector<double> initial_density;  // per phase of the cell scene
  double perturbation = 0.0;            // amplitude of a seeded random perturbation of z0
  unsigned seed = 1;
  CellObjective objective;
  OptimizerOptions optimizer;
  std::vector<double> projection_betas = {0.0};  // continuation stages (0: no projection)
  int refine = 2;         // re-check on a grid refined this many times (grid cells only)
  std::vector<int> grid;  // the cell's grid (empty for mesh files)
  std::string split = "forward";
};

struct MetamaterialRun {
  OptimizerResult result;
  double objective_gray = 0.0, objective_thresholded = 0.0, objective_refined = 0.0;
  Matrix stiffness_gray, stiffness_thresholded, stiffness_refined;
};

// The "design" section of `root`, a periodic-cell scene already parsed into `scene`
// (parse_cell_scene). Throws SceneError naming the key path (unknown keys included).
MetamaterialDesignSpec parse_metamaterial_design(const SceneNode& root, const CellScene& scene);
// Optimizes, re-checks and writes DIR/report.json, DIR/design.vtu and the plots; progress to
// `log` when set, one line per iteration to `progress` when set.
MetamaterialRun run_metamaterial_design(const CellScene& scene, const MetamaterialDesignSpec& spec,
                                        const std::string& out_dir, std::ostream* log,
                                        std::ostream* progress);

}  // namespace tailor
