#pragma once
// Oriented point sets for the meshless simulator (docs/meshless.md, "Input"): point clouds with
// normals read from text (.xyz, .pts) and PLY (ASCII or binary little-endian) files, and closed
// triangle meshes (OBJ, OFF, STL, PLY with faces) sampled into points with their face normals.
//
// Every reader throws PointInputError, whose message starts "<file>: " and names the line (text
// formats) or the point / face index (binary formats) of the first bad entry: a point without
// normals, a coordinate or normal that is not finite, a zero normal, a face that refers to a
// missing vertex, an open or non-manifold mesh (an edge not shared by exactly two faces), or
// faces whose orientations disagree. Normals are returned with unit length.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

namespace tailor {

class PointInputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OrientedPoints {
  std::string source;        // the file (or a description), for messages
  Eigen::MatrixXd positions;  // n x 3
  Eigen::MatrixXd normals;    // n x 3, unit, outward
  // Per point where it came from, for messages: the file's line (text formats), else 0.
  std::vector<int> lines;
  int size() const { return static_cast<int>(positions.rows()); }
  // "point 12 (line 14)" or "point 12".
  std::string describe(int i) const;
};

// A closed, consistently oriented triangle surface (vertices n x 3, triangles t x 3).
struct SurfaceMesh {
  std::string source;
  Eigen::MatrixXd vertices;
  Eigen::MatrixXi triangles;
  std::vector<int> face_lines;  // per triangle: its line in the file (text formats), else 0
};

struct SurfaceSamplingOptions {
  double spacing = 0.0;  // target distance between samples (> 0); 0: 1/50 of the bounding box diagonal
  unsigned seed = 1;     // of the stratified placement inside each triangle
};

// Reads by extension (case-insensitive): .xyz .pts .ply (points, or a mesh when it has faces),
// .obj .off .stl (meshes, sampled with `sampling`).
OrientedPoints read_oriented_points(const std::string& path, const SurfaceSamplingOptions& sampling = {});

// Point clouds: one point per line "x y z nx ny nz" (further columns ignored; '#' starts a
// comment; a .pts file may start with a line holding the point count).
OrientedPoints read_xyz_points(const std::string& path);
// PLY: ASCII or binary_little_endian 1.0, a "vertex" element with x y z and nx ny nz (any
// scalar types; other properties skipped). With a "face" element (a list property) the file is
// a mesh: read_ply_mesh. Big-endian files are refused.
OrientedPoints read_ply_points(const std::string& path);

SurfaceMesh read_ply_mesh(const std::string& path);
SurfaceMesh read_obj_mesh(const std::string& path);  // v and f lines (v/vt/vn indices, polygons fanned)
SurfaceMesh read_off_mesh(const std::string& path);
SurfaceMesh read_stl_mesh(const std::string& path);  // ASCII or binary; vertices welded by position

// Checks that every edge is shared by exactly two triangles traversing it in opposite directions
// (closed, manifold, consistently oriented); PointInputError naming the edge's vertices and a
// face's line otherwise. Returns the enclosed volume (negative when the faces wind inwards).
double check_closed_surface(const SurfaceMesh& mesh);

// Samples the surface: per triangle round(area / spacing^2 * 2 / sqrt(3)) points (at least one)
// at stratified barycentric positions, each with the face's unit normal; a mesh wound inwards
// (negative volume) is turned outwards. Runs check_closed_surface first.
OrientedPoints sample_surface(const SurfaceMesh& mesh, const SurfaceSamplingOptions& options);

// Checks positions and normals (finite, non-zero normals) and normalizes the normals; the
// readers call it. PointInputError naming the point.
void validate_oriented_points(OrientedPoints& points);

}  // namespace tailor
