#pragma once
// The `meshless` scene kind (docs/meshless.md, "Scenes"): a solid given by oriented points (a
// point cloud or a sampled surface mesh) or an analytic shape, discretized by MLS shape
// functions on octree nodes (forward/meshless/), with a material per node or region, clamps and
// position and rotation handles by the transformation method, gravity and point forces, and the `inverse`
// section (Young's modulus per node or per region, observations of the MLS field at points).
// The parser turns the JSON into the typed spec below; build_meshless_scene makes the model.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/core/model.hpp"
#include "forward/fem/material.hpp"
#include "forward/meshless/covering_patches.hpp"
#include "forward/meshless/implicit_surface.hpp"
#include "forward/meshless/meshless_quadrature.hpp"
#include "forward/meshless/modal_warping.hpp"
#include "forward/meshless/octree_sampling.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

class SceneNode;

struct MeshlessBox {
  Eigen::Vector3d lo, hi;
  bool contains(const Eigen::Vector3d& X) const {
    return (X.array() >= lo.array() - 1e-9).all() && (X.array() <= hi.array() + 1e-9).all();
  }
};

struct MeshlessPointForce {
  Eigen::Vector3d at, force;
};

struct MeshlessSceneSpec {
  std::string name, source, directory;
  // Geometry: a file of oriented points or a mesh (points_file), or an analytic shape.
  std::string points_file;
  double surface_spacing = 0.0;  // meshes: target sample spacing (0: 1/50 of the diagonal)
  ImplicitSurfaceOptions implicit;
  std::optional<AnalyticShape> shape;
  OctreeSamplingOptions sampling;
  MlsOptions mls;
  CoveringOptions covering;
  // Material.
  MaterialKind material = MaterialKind::neo_hookean;
  double youngs_modulus = 1000.0, poisson_ratio = 0.3, density = 1.0;
  std::vector<std::string> region_names;
  std::vector<MeshlessBox> regions;  // later regions override earlier ones
  std::vector<double> region_moduli;
  // Conditions and loads.
  std::vector<MeshlessBox> fixed;
  std::vector<MeshlessBox> handles;
  std::vector<Eigen::Vector3d> handle_displacements;
  // Rotation handles: the nodes in the box go to c + R (X - c) + d, R = exp([w]_x) (identity
  // without a rotation), c the given centre or else the centroid of the handle's nodes.
  std::vector<Eigen::Vector3d> handle_rotations;  // w = angle * unit axis [rad]
  std::vector<std::optional<Eigen::Vector3d>> handle_centers;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::vector<MeshlessPointForce> forces;
  int max_newton_iterations = 50;
  // Newton steps by CG preconditioned with a kept factorization (NewtonOptions::reuse_factorization).
  FactorReuse reuse_factorization = FactorReuse::automatic;
  // Modes and warped modal dynamics (the `modes` verb).
  int mode_count = 10;
  ModalRayleighDamping damping;
  double time_step = 0.01;
  int steps = 0;  // warped modal frames to simulate (0: none)
  std::optional<MeshlessPointForce> modal_force;  // applied during the first half of the steps
  // The handles' spring stiffness k in the warped dynamics, as a multiple of the largest modal
  // eigenvalue (docs/meshless.md, "Modal warping"): 1e4 meets the targets to ~1e-4 of the
  // elastic response; smaller values leave the handles soft.
  double handle_stiffness = 1e4;
  int frame_every = 10;
  // Inverse design.
  struct Inverse {
    bool per_region = true;
    std::vector<Eigen::Vector3d> observed;  // points where the MLS field is observed
    Eigen::MatrixXd targets;                // observed.size() x 3 target positions
    double regularization = 0.0;
    OptimizerOptions optimizer;
    unsigned seed = 1;
  };
  std::optional<Inverse> inverse;
};

// Throws SceneError naming the source and key path (unknown keys included).
MeshlessSceneSpec parse_meshless_scene(const SceneNode& root, const std::string& directory);

struct MeshlessScene {
  MeshlessSceneSpec spec;
  std::shared_ptr<const ImplicitSurface> surface;  // point input only
  OctreeSampling sampling;
  Eigen::VectorXd patch_spacing;  // per node: R_a / support_factor after cover_points
  CoveringReport covering;
  std::shared_ptr<MlsShapeFunctions> mls;
  std::shared_ptr<MeshlessQuadrature> quadrature;
  std::unique_ptr<Model> model;
  // The handles' nodes and their target positions c + R (X - c) + d, R = exp([w]_x).
  struct Handle {
    std::vector<int> nodes;
    Eigen::MatrixXd targets;  // nodes.size() x 3
    Eigen::Vector3d rotation = Eigen::Vector3d::Zero(), center = Eigen::Vector3d::Zero();
  };
  std::vector<Handle> handles;
  // With handles: the elimination of the `fixed` boxes alone (the handles act in the warped
  // modal dynamics as springs, so the modes leave their nodes free).
  std::optional<Elimination> fixed_elimination;
  Vector p;                      // [E per node, nu per node]
  std::vector<int> region_of_node;  // 0: no region, r + 1: spec.regions[r]
  Eigen::MatrixXd samples;       // output points: the surface samples, else the quadrature points
  double seconds_implicit = 0.0, seconds_sampling = 0.0, seconds_quadrature = 0.0;
  int num_nodes() const { return static_cast<int>(sampling.nodes.rows()); }
  Vector rest() const;
  double size() const;  // the bounding box diagonal
};

// Reads the points, builds the implicit surface, the nodes, the quadrature and the model.
// SceneError naming the scene for input errors (PointInputError and MeshlessPointError included).
std::unique_ptr<MeshlessScene> build_meshless_scene(const MeshlessSceneSpec& spec);

// The design problem of spec.inverse: E = E0 exp(z) per region or per node.
struct MeshlessInverse {
  ParameterizationPtr parameterization;
  ObjectivePtr objective;
  std::unique_ptr<StaticFunctional> functional;
  Vector z0;
  std::vector<std::string> labels;
};
std::unique_ptr<MeshlessInverse> build_meshless_inverse(const MeshlessScene& scene);

}  // namespace tailor
