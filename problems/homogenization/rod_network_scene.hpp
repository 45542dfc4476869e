#pragma once
// The "rod_network" section of a periodic-cell scene (docs/homogenization.md, "Rod-network
// cells"): a planar periodic network of discrete elastic rods, given as a pattern
//   "rod_network": {"pattern": "square" | "honeycomb", "bar_length": 1, ...}
// or explicitly
//   "rod_network": {"lattice": [[a11, a12], [a21, a22]], "joints": [[x, y], ...],
//                   "bars": [{"from": 0, "to": 1, "shift": [0, 1]}, ...], ...}
// with "radius", "youngs_modulus", "shear_modulus" or "poisson_ratio", "edges_per_bar" (16)
// and "depth" (optional: the sheet depth that turns the membrane stiffness into moduli).
#include "forward/homogenization/rod_network.hpp"

namespace tailor {

class SceneNode;

struct RodNetworkScene {
  RodNetwork network;
  double depth = 0.0;  // 0: report the membrane stiffness only
};

// Throws SceneError naming the source and key path (unknown keys, bad values, and what
// RodNetwork::validate() rejects, under the section's path).
RodNetworkScene parse_rod_network_scene(const SceneNode& section);

}  // namespace tailor
