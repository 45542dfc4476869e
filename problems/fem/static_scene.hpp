#pragma once
// Static equilibrium of a scene: build the mesh, the per-element material parameters, the
// Dirichlet elimination and the external loads from a parsed Scene (StaticSetup), compose a
// Model from them, and solve with Newton, optionally ramping loads over several steps.
//
// Units are whatever the scene uses, consistently (e.g. SI: m, Pa, N, kg/m^3).
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "adjoint/derivative_check.hpp"
#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/mesh/quadratic_mesh.hpp"
#include "forward/solve/newton.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

// One ElasticTerm to build: a material model over a subset of the mesh's elements.
struct MaterialBlock {
  MaterialKind kind;
  std::vector<int> elements;                                    // mesh element indices, increasing
  std::shared_ptr<const PrincipalStretchCurves> spline_curves;  // set: a SplineMaterial (kind unused)
};

struct StaticSetup;
// A user's energy term, made for a setup (its mesh, supports, loads): added to every model
// build_static_model makes, at full strength (not ramped by load steps). It sees the parameter
// layout of build_static_model ("youngs_modulus", "poisson_ratio", then a design's own blocks).
using EnergyTermFactory = std::function<std::unique_ptr<EnergyTerm>(const StaticSetup& setup)>;

// Everything a static solve needs, checked against the mesh. Vectors over DOFs are interleaved
// like the state (index dim * node + component).
//
// Quadratic elements ("mesh": {"order": 2}): `quadratic` holds the P2 mesh whose corners are
// `mesh`, and the state holds every node, the corners first (node v < mesh.num_vertices() is
// vertex v), so a vertex's DOFs are where they are for linear elements and every vertex-indexed
// input (selectors, observations, nodal forces) keeps its meaning. Per-element data are per
// element of either. Outputs per vertex (displacement, VTU) are the corners'.
struct StaticSetup {
  Mesh mesh;
  std::shared_ptr<const QuadraticMesh> quadratic;  // set: quadratic elements over mesh
  std::vector<MaterialBlock> materials;
  Eigen::VectorXi element_material;  // per element: index into materials (= scene.materials)
  Eigen::VectorXd youngs_modulus;    // per element
  Eigen::VectorXd poisson_ratio;     // per element
  Eigen::VectorXd density;           // per element
  std::vector<int> fixed_dofs;       // increasing
  Vector prescribed_displacement;    // per DOF, at full load; zero on free DOFs
  Vector nodal_forces;               // per DOF, the total external load at full load
  bool has_loads = false;            // whether the scene has any load (adds an ExternalForceTerm)
  SolverSpec solver;
  std::vector<EnergyTermFactory> extra_terms;  // user energy terms (not from the scene file)

  int dim() const { return mesh.dim(); }
  int num_nodes() const { return quadratic ? quadratic->num_nodes() : mesh.num_vertices(); }
  int num_dofs() const { return mesh.dim() * num_nodes(); }
  int order() const { return quadratic ? 2 : 1; }
  Vector rest_state() const;  // rest positions of every node, interleaved
  Vector parameters() const;  // p: blocks "youngs_modulus" then "poisson_ratio"
};

// The rigid motions (named as unconstrained_rigid_motions, forward/reduction/free_space.hpp) that
// leave every DOF of `fixed_dofs` in place. With quadratic elements the vertices' DOFs decide:
// an edge node is held only with both its ends.
std::vector<std::string> free_rigid_motions(const StaticSetup& setup, const std::vector<int>& fixed_dofs);

// Builds the mesh (generated or read) and resolves every selector and load. Throws SceneError
// for scene problems found against the mesh, MeshError for mesh files.
StaticSetup setup_static_scene(const Scene& scene);
// A static equilibrium needs supports that leave no rigid motion free (its stiffness matrix is
// singular otherwise): throws a SceneError at "dirichlet" naming the free motions.
void require_supported(const Scene& scene, const StaticSetup& setup);

// Quadratic elements ("mesh": {"order": 2}) serve static solves (simulate, check) and inverse
// problems on the full-space adjoint; every other use (`what`, e.g. "dynamics") calls this
// first, which throws a SceneError at "mesh.order" for an order-2 scene.
void require_linear_elements(const Scene& scene, const std::string& what);

// The Model at a load factor s in (0, 1]: one ElasticTerm per material block, one
// ExternalForceTerm with s * nodal_forces when the scene has loads, the extra_terms, and Dirichlet
// elimination with x = rest + s * prescribed_displacement on the fixed DOFs.
std::unique_ptr<Model> build_static_model(const StaticSetup& setup, double load_factor);

struct LoadStep {
  double load_factor = 1.0;
  NewtonResult newton;
};

struct StaticSolution {
  bool converged = false;
  std::string status;           // NewtonStatus of the last step attempted ("converged", ...)
  std::string message;          // why it stopped (prefixed by the load step when there are several)
  std::vector<LoadStep> steps;  // the steps attempted (stops at the first failure)
  int num_free = 0;
  Vector positions;               // final state x (the last iterate when the solve failed)
  Eigen::MatrixXd displacement;   // num_vertices x dim (the corners' with quadratic elements)
  double energy = 0.0;            // total potential at the final state and load factor
  // |S^T dE/dx| at the final state, evaluated afresh; a converged solve whose last Newton
  // residual it exceeds tenfold (and the floor) is reported as status "inconsistent_residual".
  double residual = 0.0;
  double max_displacement = 0.0;  // largest vertex displacement norm
  int max_displacement_vertex = 0;
  // Sum over Dirichlet DOFs of -dE_elastic/dx, per component: the force the body exerts on its
  // supports (they push back with the opposite force). At equilibrium it equals the total load
  // applied to free DOFs.
  Eigen::VectorXd reaction_force_total;
  Eigen::MatrixXd stresses;  // num_elements x dim*dim: first Piola-Kirchhoff stress, row-major
  // Seconds, summed over load steps.
  double analysis_seconds = 0, assembly_seconds = 0, factorization_seconds = 0, solve_seconds = 0,
         line_search_seconds = 0, model_seconds = 0;
};

// Solves for static equilibrium, from the rest state, in setup.solver.load_steps steps with
// warm starts. `progress`: Newton iterations and load steps are printed there when set.
StaticSolution solve_static(const StaticSetup& setup, std::ostream* progress = nullptr);
// The same from the state `start` (positions, interleaved, e.g. a reduced model's solution), at
// full load in one step; when that does not converge, solve_static's path from rest.
StaticSolution solve_static_from(const StaticSetup& setup, const Vector& start,
                                 std::ostream* progress = nullptr);

// Derivative checks of every energy term of the full-load model at the prescribed state plus
// a random perturbation of 2% of the mean element size (seeded), with exact Hessians.
std::vector<EnergyTermCheck> check_static_scene(const StaticSetup& setup, unsigned seed = 1);
// A check fails unless it passed or both analytic and finite differences vanish (e.g. the
// Hessian of a linear load term).
bool check_failed(const EnergyTermCheck& check);

}  // namespace tailor
