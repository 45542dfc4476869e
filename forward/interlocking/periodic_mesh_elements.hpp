#pragma once
// Triangle-mesh elements of a periodic rigid cell (docs/interlocking.md, "Mesh bodies in cells").
//
// A CellElement with a mesh is a rigid body whose surface is that mesh: vertex V (element frame)
// sits at T + R(w) V in the world, with (T, w) the element's rigid DOFs (forward/rigid); its
// contact is the IPC barrier on triangles (periodic_mesh_contact.hpp) instead of the implicit
// torus distance. The element frame's origin is the element's position (not necessarily its
// centre of mass: a static cell has no inertia).
//
// Meshed torus (torus_surface of forward/tori, vertices on the surface): `major` rings of `minor`
// vertices. Chordal error (the Hausdorff distance between the mesh and the torus surface), by the
// argument of torus.hpp for the inscribed mesh: a point of a triangle is l p + (1 - l) q with p,
// q on the polygonal sections of two adjacent rings; the polygon lies between the tube circle
// and the circle r cos(pi / minor), and the combination of the two rings moves a point towards
// the axis by at most (R + r)(1 - cos(pi / major)), so
//   delta <= r (1 - cos(pi / minor)) + (R + r)(1 - cos(pi / major))      (r: max(r, r1))
// and the mesh converges to the torus as delta ~ (pi^2 / 2)(r / minor^2 + (R + r) / major^2).
#include <Eigen/Core>
#include <memory>
#include <string>

#include "forward/interlocking/periodic_cell.hpp"

namespace tailor::interlocking {

struct ElementMesh {
  Eigen::MatrixX3d vertices;   // element frame [length]
  Eigen::MatrixX3i faces;      // closed surface, outward triangles
  std::string source;          // what it is, for reports ("torus 32 x 16", a file name)
  double chordal_error = 0.0;  // bound on the distance to the surface it stands for [length]; 0: exact
};

// The meshed torus of `shape` (see above), its chordal_error set to the bound above.
std::shared_ptr<const ElementMesh> torus_mesh(const tori::TorusShape& shape, int major, int minor);
double torus_chordal_bound(const tori::TorusShape& shape, int major, int minor);

// A closed triangle surface from an OBJ ("v x y z", "f a b c" with 1-based indices, "a/b/c"
// forms accepted) or OFF file (by extension, .obj / .off); polygons with more than three
// vertices are refused. Throws std::runtime_error naming the file and the line.
std::shared_ptr<const ElementMesh> read_element_mesh(const std::string& path);

// Throws std::invalid_argument (naming `where`) unless the mesh has vertices and faces, finite
// coordinates, indices in range and no degenerate (zero-area) triangle.
void validate_element_mesh(const ElementMesh& mesh, const std::string& where);

// max |V| over the vertices: every surface point lies within it of the element's position.
double mesh_bounding_radius(const ElementMesh& mesh);

// The cell with every element replaced by the meshed torus of its shape (placements kept).
RigidCellSpec with_torus_meshes(RigidCellSpec spec, int major, int minor);

// True when the cell's elements are meshes (all of them; validate_cell refuses a mix).
bool is_mesh_cell(const RigidCellSpec& spec);

}  // namespace tailor::interlocking
