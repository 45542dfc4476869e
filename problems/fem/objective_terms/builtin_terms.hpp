#pragma once
// The settings of tailor's own objective term types (one file each in this folder, registered in
// problems/fem/objective_term_registry.hpp; the "handles" term's are in inverse_handles_spec.hpp)
// and what the data terms share. The scene format is in docs/scenes.md.
//
// Data terms compare displacements u of some vertices with wanted ones u*; their objective is
// 1/2 |u - u*|^2 and their scale |u*|^2, so weight * term / scale is the relative misfit (n L^2
// replaces |u*|^2 when every u* is zero, L the mesh's bounding-box diagonal): a weight of 1 means
// the same in every scene and the optimizer's absolute tolerances carry over between scenes.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "objectives/material_smoothness.hpp"
#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/objective_term_registry.hpp"

namespace tailor {

// "target_displacements": the same wanted displacement for every selected vertex.
struct TargetDisplacementsTerm : ObjectiveTermSettings {
  VertexSelector vertices;
  Eigen::VectorXd displacement;
};

// "observations": measured displacements from a file, one "vertex ux uy [uz]" per line.
struct ObservationsTerm : ObjectiveTermSettings {
  std::string file;               // resolved path, for messages
  std::vector<int> vertices;      // one per line, distinct
  Eigen::MatrixXd displacements;  // one row per line, 2 or 3 columns
};

// "synthetic_observations": observations simulated from a true Young's modulus field, with noise.
struct SyntheticObservationsTerm : ObjectiveTermSettings {
  VertexSelector vertices;
  ModulusField youngs_modulus;  // the truth the observations are simulated from
  double noise = 0.0;           // relative: std. deviation = noise * largest observed |u|
  unsigned seed = 1;
};

// "smoothness": jumps of the designed per-element field across shared facets.
struct SmoothnessTerm : ObjectiveTermSettings {
  bool logarithmic = true;  // penalize jumps of log E (ratios) rather than of E
  AdjacencyWeighting weighting = AdjacencyWeighting::unit;
};

// "tikhonov": J = 1/2 sum_e ((E_e - prior) / prior)^2.
struct TikhonovTerm : ObjectiveTermSettings {
  double prior = 1.0;
};

// The data terms' objective: 1/2 |u - u*|^2 over `vertices` (rows of `displacements`), with
// the scale |u*|^2 of the comment above.
BuiltObjectiveTerm displacement_misfit(const InverseProblem& problem, std::vector<int> vertices,
                                       const Eigen::MatrixXd& displacements);

}  // namespace tailor
