#pragma once
// The periodic-cell scene (`"type": "periodic_cell"`), read by `tailor homogenize` and, with a
// "design" section, by `tailor run` (docs/homogenization.md lists every key):
//   {
//     "type": "periodic_cell", "name": "hex_holes",
//     "cell": {"lattice": [[1, 0], [0.5, 0.866]], "origin": [0, 0],
//              "grid": [24, 24], "split": "crossed"        (or "mesh": "cell.msh"),
//              "tolerance": 1e-8},
//     "plane": "strain" | "stress",                          (2D only; default strain)
//     "materials": [{"youngs_modulus": 1, "poisson_ratio": 0.3}, ...],  (phase 0, 1, ...)
//     "phases": [{"phase": 1, "disc": {"center": [0.5, 0.5], "radius": 0.3}},
//                {"phase": 1, "slab": {"axis": 1, "from": 0.0, "to": 0.5}}],
//     "directions": 360,
//     "stress_strain": {"material": "neo_hookean", "max_strain": 0.3, "steps": 10,
//                       "directions": [[1, 0], [0, 1]]},        (nonlinear curves)
//     "design": {...}                                       (problems/metamaterial)
//   }
// or, for a periodic rod network, "rod_network": {...} (rod_network_scene.hpp) in place of
// "cell", "materials", "phases", "plane", "stress_strain" and "design".
// Elements start in the phase of their mesh region: region r takes materials[r] (0 for generated
// meshes), or, when every material names a "region" (the mesh file's physical tag, e.g. Gmsh's
// 1 and 2), the material naming the element's tag. Each "phases" rule
// then moves the elements whose centroid it contains (later rules win). Discs (spheres in
// 3D) use the distance to the nearest periodic image of the centre (Cartesian); slabs use the
// fractional coordinate along lattice vector `axis` of the centroid.
#include <optional>
#include <string>
#include <vector>

#include "forward/fem/material.hpp"
#include "forward/homogenization/linear_homogenization.hpp"
#include "problems/homogenization/rod_network_scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

class SceneNode;

struct CellPhase {
  double youngs_modulus;
  double poisson_ratio;
};

// Optional nonlinear curves: uniaxial macro strain F = I + t d d^T, t = 0..max_strain.
struct StressStrainSpec {
  MaterialKind material = MaterialKind::neo_hookean;
  double max_strain = 0.2;
  int steps = 10;
  std::vector<Vector> directions;
};

struct CellScene {
  std::string name;
  std::string source;  // the scene in messages (its file)
  PeriodicCell cell;
  PlaneMode plane = PlaneMode::plane_strain;
  std::vector<CellPhase> materials;
  std::vector<int> element_phase;  // per element
  int directions = 360;            // samples of E(d) over 360 degrees per plane
  bool has_design = false;
  std::optional<StressStrainSpec> stress_strain;
  // A rod-network cell ("rod_network" instead of "cell" and "materials"; rod_network_scene.hpp):
  // then `cell`, `materials` and `element_phase` are empty.
  std::optional<RodNetworkScene> rod_network;
  Vector youngs_modulus() const;
  Vector poisson_ratio() const;
};

// The scene's document; `directory` resolves the mesh file's path. The name is left empty when
// the scene gives none. Throws SceneError naming the source and key path (unknown keys
// included), MeshError for mesh files, and SceneError carrying the PeriodicityError message for
// a non-periodic mesh. The design section is parse_metamaterial_design's.
CellScene parse_cell_scene(const SceneNode& root, const std::string& directory);

}  // namespace tailor
