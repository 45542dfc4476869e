#pragma once
// Reduced material design with Laplacian material modes (Xu, Li, Chen, Barbic, "Interactive
// material design using model reduction", TOG 2015; docs/methods.md section 5): instead of one
// variable per element, the per-element field y is restricted to the span of the r lowest
// eigenvectors of L y = lambda V y (forward/reduction/material_modes.hpp),
//
//   y = Phi z + y0,   E = g(y)   per element,
//
// with y0 the per-element pre-image of the initial moduli (so z = 0 reproduces them exactly,
// also when they are not uniform) and g the value map:
//   log map, bounds [a, b]:  E = exp(log a + (log b - log a) (1 + tanh y) / 2)   (the default)
//   log map, no bounds:      E = exp(y)
//   identity map, [a, b]:    E = a + (b - a) (1 + tanh y) / 2
// Bounds on E cannot be optimizer bounds on z once E mixes modes, so a smooth box keeps every
// element's E strictly inside [a, b] whatever z is; in log space a step in y is the same
// relative change of E at any scale. r = "full" (no count) means no reduction: y = z, one
// variable per element, z0 = y0 (with the log map and no bounds exactly the per-element
// design).
#include <optional>
#include <string>

#include "adjoint/parameterization.hpp"
#include "forward/mesh/element_laplacian.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

struct ModalDesignOptions {
  std::optional<int> modes;  // r; nullopt = full (per element)
  AdjacencyWeighting weighting = AdjacencyWeighting::facet_over_distance;
  bool logarithmic = true;             // the log map (else identity)
  std::optional<double> lower, upper;  // both or neither; identity needs both
};

struct ModalDesign {
  Matrix modes;                     // Phi, num_elements x r, V-orthonormal; empty for full
  Vector eigenvalues;               // r, ascending
  Vector offset;                    // y0 per element
  ParameterizationPtr element_map;  // z -> E per element
  Vector z0;                        // 0 (r modes) or y0 (full)
  double seconds = 0.0;             // computing the modes (eigen solve)
  std::string eigen_message;        // the eigen solver's report
};

// Per element: y = value_map^-1(E). Throws std::invalid_argument when some E is not strictly
// inside the bounds (or not > 0 for the log map).
Vector modal_preimage(const Eigen::VectorXd& youngs_modulus, const ModalDesignOptions& options);

// Throws std::invalid_argument for options out of range (r not in [1, num_elements - 1],
// unpaired bounds, the identity map without bounds, initial moduli outside the open box) and
// std::runtime_error when the eigen solve fails.
ModalDesign modal_design(const Mesh& mesh, const Eigen::VectorXd& initial_youngs_modulus,
                         const ModalDesignOptions& options);

}  // namespace tailor
