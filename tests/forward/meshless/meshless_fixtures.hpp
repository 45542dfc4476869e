#pragma once
// Shared set-ups of the meshless tests: a sampled analytic solid with its MLS shape functions
// and quadrature, and the linear solve.
#include <gtest/gtest.h>

#include <memory>

#include "forward/core/model.hpp"
#include "forward/meshless/meshless_quadrature.hpp"
#include "forward/meshless/mls_shape_functions.hpp"
#include "forward/meshless/octree_sampling.hpp"
#include "forward/solve/newton.hpp"
#include "../../support/equilibrium.hpp"

namespace tailor::meshless_testing {

struct MeshlessSolid {
  OctreeSampling sampling;
  std::shared_ptr<MlsShapeFunctions> mls;
  std::shared_ptr<MeshlessQuadrature> quadrature;
  int num_nodes() const { return static_cast<int>(sampling.nodes.rows()); }
  Vector rest() const {
    const Eigen::MatrixXd t = sampling.nodes.transpose();
    return Eigen::Map<const Vector>(t.data(), t.size());
  }
};

inline MeshlessSolid make_solid(const AnalyticShape& shape, double spacing, int quadrature_order, int boundary_depth,
                                MlsOptions mls_options = {}) {
  MeshlessSolid s;
  s.sampling = sample_shape(shape, {spacing, quadrature_order, boundary_depth});
  s.mls = std::make_shared<MlsShapeFunctions>(s.sampling.nodes, s.sampling.spacing, mls_options);
  s.quadrature = std::make_shared<MeshlessQuadrature>(
      build_meshless_quadrature(*s.mls, s.sampling.points, s.sampling.weights));
  return s;
}

// Parameters [E per node, nu per node].
inline Vector uniform_parameters(int nodes, double youngs_modulus, double poisson_ratio) {
  Vector p(2 * nodes);
  p.head(nodes).setConstant(youngs_modulus);
  p.tail(nodes).setConstant(poisson_ratio);
  return p;
}

// The equilibrium of `model` from its rest state (checked to converge).
using tailor::testing::solve_equilibrium;

}  // namespace tailor::meshless_testing
