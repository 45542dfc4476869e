#pragma once
// Resolving a scene's selectors against its mesh: which vertices, elements and boundary
// facets a selector picks. A selector that picks nothing, or does not fit the mesh (an axis or
// an id the mesh lacks), is a SceneError naming the selector's key path.
#include <string>
#include <vector>

#include "forward/mesh/mesh.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

// Throws SceneError "<scene.source>: <key>: <what>".
[[noreturn]] void throw_scene_error(const Scene& scene, const std::string& key, const std::string& what);

// Checks that `v` has one entry per mesh dimension.
void check_dimension(const Scene& scene, const Mesh& mesh, const Eigen::VectorXd& v, const std::string& key);

// Default distance tolerance of plane and box selectors: 1e-9 times the bounding-box diagonal.
double default_selection_tolerance(const Mesh& mesh);

// Selected vertex ids, increasing and unique (never empty).
std::vector<int> select_vertices(const Scene& scene, const Mesh& mesh, const VertexSelector& selector);
// Selected element indices, increasing (never empty).
std::vector<int> select_elements(const Scene& scene, const Mesh& mesh, const ElementSelector& selector);
// Boundary facets (rows, outward oriented) whose vertices are all selected (never empty).
Eigen::MatrixXi select_boundary_facets(const Scene& scene, const Mesh& mesh, const VertexSelector& selector);

}  // namespace tailor
