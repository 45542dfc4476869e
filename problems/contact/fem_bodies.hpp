#pragma once
// FEM bodies in contact scenes (internal to problems/contact): a `fem_bodies` entry holds the
// FEM scene's keys (mesh, materials, dirichlet, loads; docs/scenes.md), parsed by the FEM scene
// parser; its model (elasticity and loads over its own vertex DOFs) is placed after the rigid
// DOFs of the contact model by EmbeddedTerm, and its boundary triangles join the contact.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"
#include "problems/contact/rigid_scene.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

// The boundary triangles of a tetrahedral mesh over its boundary vertices only: faces in
// surface indices, mesh_vertex[i] the mesh vertex of surface vertex i.
void boundary_surface(const Mesh& mesh, Eigen::MatrixX3i& faces, std::vector<int>& mesh_vertex);

// One `fem_bodies` entry: "name" plus the FEM scene's "mesh", "materials", "dirichlet", "loads".
// The scene's gravity is added to loads.gravity (unless given) when a material has a density.
FemBodySpec parse_fem_body(const SceneNode& node, const Eigen::Vector3d& gravity, const std::string& source,
                           const std::string& directory);

// An FEM body built for a contact model: its static setup and model over its own DOFs
// (0 .. 3 n - 1) and parameters (its "youngs_modulus" and "poisson_ratio" blocks), where they
// sit in the contact model, and its boundary surface.
struct FemBodyPart {
  std::string name;
  StaticSetup setup;
  std::unique_ptr<Model> model;
  Vector parameters;
  int dof_offset = 0, parameter_offset = 0;
  Eigen::MatrixX3i faces;
  std::vector<int> mesh_vertex;
};

// Throws SceneError for scene problems found against the mesh (names the body).
FemBodyPart build_fem_body(const FemBodySpec& spec, int dof_offset, int parameter_offset);

}  // namespace tailor
