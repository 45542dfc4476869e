#pragma once
// Reading and writing meshes. Every reader validates the result (validate_mesh) and throws
// MeshError naming the file, the line and what is wrong.
#include <map>
#include <string>

#include "forward/mesh/mesh.hpp"

namespace tailor {

// Gmsh .msh, ASCII format 2.x and 4.x. Keeps tetrahedra (3D) or, when a file has none,
// triangles (2D, z dropped). Physical tags become element_regions.
Mesh read_gmsh(const std::string& path);
// Medit .mesh (Tetrahedra, or Triangles when there are none; the reference of each element
// becomes its region).
Mesh read_medit(const std::string& path);
// TetGen: `base.node` + `base.ele` (path may name either file or the base name). The first
// region attribute, when present, becomes element_regions.
Mesh read_tetgen(const std::string& path);
// Dispatches on the extension (.msh, .mesh, .node/.ele).
Mesh read_mesh(const std::string& path);

// Fields for VTK output; point fields have num_vertices rows, cell fields num_elements rows.
// A field with 1 column is a scalar, with dim columns a vector (padded to 3 for VTK), with
// dim*dim columns a tensor (row-major).
struct VtkFields {
  std::map<std::string, Eigen::MatrixXd> point;
  std::map<std::string, Eigen::MatrixXd> cell;
};
// VTK XML unstructured grid (.vtu, ASCII) for ParaView. `positions` (num_vertices x dim)
// replaces rest positions when given (pass a deformed shape), otherwise rest positions.
void write_vtu(const std::string& path, const Mesh& mesh, const VtkFields& fields = {},
               const Eigen::MatrixXd* positions = nullptr);

}  // namespace tailor
