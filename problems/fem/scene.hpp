#pragma once
// A static scene as typed data: the mesh, the materials over element subsets, Dirichlet
// conditions, loads and solver settings. JSON is parsed and validated once, here, at the edge
// (see docs/scenes.md for the format); everything downstream works on these structs.
//
// Checks that need the mesh (selectors that select nothing, element coverage, vector lengths
// against a mesh read from a file) happen when the scene is built (static_scene.hpp); each
// spec therefore keeps the JSON key path it came from, so those errors name it too.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/fem/material.hpp"
#include "forward/fem/materials/principal_stretch_curves.hpp"
#include "forward/solve/newton.hpp"
#include "forward/solve/threads.hpp"
#include "problems/scene_error.hpp"

namespace tailor {

struct MeshSpec {
  enum class Kind { file, box, rectangle };
  Kind kind = Kind::box;
  std::string file;          // kind == file: path resolved against the scene's folder
  Eigen::VectorXd min, max;  // box (3) / rectangle (2) corners
  Eigen::VectorXi cells;     // cells per axis, each >= 1
  // 1: linear elements (4-node tets, 3-node triangles); 2: quadratic ones (10-node tets, 6-node
  // triangles; forward/mesh/quadratic_mesh.hpp) over the same corners, for static scenes.
  int order = 1;
};

// Which elements a material covers.
struct ElementSelector {
  enum class Kind { all, region, box };
  Kind kind = Kind::all;
  int region = 0;            // kind == region: element_regions value
  Eigen::VectorXd min, max;  // kind == box: element centroid inside, bounds included
  std::string key;           // JSON key path, for errors found against the mesh
};

// Which vertices a condition or load acts on. A "file" selector is read at parse time and
// becomes a list.
struct VertexSelector {
  enum class Kind { plane, box, list, boundary };  // boundary: every vertex on the surface
  Kind kind = Kind::list;
  int axis = 0;              // plane: 0, 1, 2 for x, y, z
  double value = 0.0;        // plane: coordinate value
  double tolerance = -1.0;   // plane and box: distance tolerance; < 0 = 1e-9 * bounding-box diagonal
  Eigen::VectorXd min, max;  // box: bounds (included)
  std::vector<int> ids;      // list: vertex ids (>= 0; range checked against the mesh)
  std::string key;
};

struct MaterialSpec {
  ElementSelector elements;
  MaterialKind model = MaterialKind::linear;  // unused when spline_curves is set
  // "model": "spline": the principal-stretch curves (from a preset with E and nu, inline, or a
  // file). youngs_modulus and poisson_ratio then hold the curves' small-strain values (for
  // outputs); the elastic energy ignores them.
  std::shared_ptr<const PrincipalStretchCurves> spline_curves;
  double youngs_modulus = 0.0;                // used when youngs_modulus_values is empty
  std::vector<double> youngs_modulus_values;  // from youngs_modulus_file: one per mesh element
  double poisson_ratio = 0.0;
  double density = 0.0;  // mass per unit volume (per unit thickness in 2D)
  std::string key;       // "materials[i]"
};

struct DirichletSpec {
  VertexSelector vertices;
  Eigen::VectorXd displacement;  // prescribed displacement; empty = zero
  std::vector<int> components;   // constrained components; empty = all
  std::string key;
};

struct TractionSpec {
  VertexSelector faces;      // boundary facets whose vertices are all selected
  Eigen::VectorXd traction;  // force per unit area (per unit length in 2D)
  std::string key;
};

struct NodalForceSpec {
  VertexSelector vertices;
  Eigen::VectorXd force;  // applied to each selected vertex
  std::string key;
};

// Nodal forces read from a text file with lines "vertex fx fy [fz]".
struct NodalForceFile {
  std::vector<int> vertices;
  Eigen::MatrixXd forces;  // one row per line, 2 or 3 columns
  std::string key;
};

struct LoadSpec {
  std::optional<Eigen::VectorXd> gravity;  // acceleration; needs material densities
  std::string gravity_key = "loads.gravity";
  std::vector<TractionSpec> tractions;
  std::vector<NodalForceSpec> nodal;
  std::optional<NodalForceFile> nodal_file;
  bool any() const { return gravity || !tractions.empty() || !nodal.empty() || nodal_file; }
};

struct SolverSpec {
  // max_iterations, tolerances, hessian mode (progress is set by the caller), and the linear
  // solver of "linear_solver" (problems/fem/linear_solver_choice.hpp): empty for CHOLMOD, else made
  // once by the registered factory and shared by every solve of the scene (one at a time).
  NewtonOptions newton;
  std::string linear_solver = "cholmod";  // solver.linear_solver
  int load_steps = 1;  // loads and prescribed displacements ramp linearly over this many solves
  std::optional<ThreadSettings> threads;  // solver.threads: applied by the CLI before the run
};

class SceneNode;      // problems/scene_node.hpp
struct InverseSpec;   // problems/fem/inverse_scene.hpp
struct DynamicsSpec;  // problems/fem/dynamic_scene.hpp

struct Scene {
  std::string name;       // defaults to the file's stem
  std::string source;     // how error messages name the scene (the file path as given)
  std::string directory;  // folder relative paths are resolved against
  MeshSpec mesh;
  std::vector<MaterialSpec> materials;
  std::vector<DirichletSpec> dirichlet;
  LoadSpec loads;
  SolverSpec solver;
  // The optional "inverse" section (what to design, the objective, the optimizer), used by
  // `tailor run` and `tailor gradcheck`; shared because it is immutable once parsed.
  std::shared_ptr<const InverseSpec> inverse;
  // The optional "dynamics" section: `tailor simulate` integrates in time instead.
  std::shared_ptr<const DynamicsSpec> dynamics;
};

// Parses scene JSON text. `source` names the scene in messages, `directory` resolves relative
// paths (mesh and data files are read here, except the mesh itself). Throws SceneError.
Scene parse_scene(const std::string& json_text, const std::string& source, const std::string& directory);
// The same on a parsed document (SceneFile::node(), problems/scene_kinds.hpp).
Scene parse_scene(const SceneNode& root, const std::string& directory);
// Reads and parses a scene file; the default name is the file's stem. Throws SceneError.
Scene read_scene(const std::string& path);

// 0, 1, 2 for "x", "y", "z".
std::string axis_name(int axis);

}  // namespace tailor
