#include "forward/reduction/material_modes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::material_modes_test {
namespace {

Mesh small_box() { return box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 1.3, 1.7), 3, 4, 5); }

SparseMatrix volume_matrix(const Mesh& mesh) {
  const Vector v = element_volumes(mesh);
  Triplets t;
  for (Eigen::Index e = 0; e < v.size(); ++e) t.emplace_back(static_cast<int>(e), static_cast<int>(e), v[e]);
  SparseMatrix m(v.size(), v.size());
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

void expect_modes_valid(const Mesh& mesh, const MaterialModes& modes, AdjacencyWeighting weighting,
                        double residual_tol) {
  const int m = mesh.num_elements();
  const Eigen::Index r = modes.eigenvalues.size();
  ASSERT_EQ(modes.modes.rows(), m);
  ASSERT_EQ(modes.modes.cols(), r);
  const Vector volumes = element_volumes(mesh);
  // First mode: the constant 1 / sqrt(total volume), eigenvalue 0.
  const double c = 1.0 / std::sqrt(volumes.sum());
  EXPECT_LT((modes.modes.col(0).array() - c).abs().maxCoeff(), 1e-8 * c);
  EXPECT_NEAR(modes.eigenvalues[0], 0.0, 1e-10 * std::max(1.0, modes.eigenvalues[r - 1]));
  for (Eigen::Index k = 1; k < r; ++k) {
    EXPECT_GT(modes.eigenvalues[k], 0.0);
    EXPECT_LE(modes.eigenvalues[k - 1], modes.eigenvalues[k]);
  }
  const Matrix gram = modes.modes.transpose() * volumes.asDiagonal() * modes.modes;
  EXPECT_LT((gram - Matrix::Identity(r, r)).cwiseAbs().maxCoeff(), 1e-10);
  const SparseMatrix L = element_adjacency_laplacian(mesh, weighting);
  for (Eigen::Index k = 0; k < r; ++k) {
    const Vector y = modes.modes.col(k);
    const Vector res = L * y - modes.eigenvalues[k] * volumes.cwiseProduct(y);
    EXPECT_LT(res.norm(), residual_tol * (L * y).norm() + 1e-12 * y.norm()) << "mode " << k;
  }
}

TEST(MaterialModes, LaplacianIsSymmetricWithZeroRowSums) {
  const Mesh mesh = small_box();
  for (AdjacencyWeighting w : {AdjacencyWeighting::unit, AdjacencyWeighting::facet_over_distance}) {
    const SparseMatrix L = element_adjacency_laplacian(mesh, w);
    EXPECT_EQ(L.rows(), mesh.num_elements());
    EXPECT_LT(Matrix(L - SparseMatrix(L.transpose())).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT((L * Vector::Ones(L.cols())).cwiseAbs().maxCoeff(), 1e-12);
    // Each interior tet has 4 face neighbours: with unit weights the diagonal is the degree.
    if (w == AdjacencyWeighting::unit) {
      EXPECT_EQ(L.diagonal().maxCoeff(), 4.0);
      EXPECT_GE(L.diagonal().minCoeff(), 1.0);
    }
  }
}

TEST(MaterialModes, FacetOverDistanceWeightOfTwoUnitTriangles) {
  // Unit square split along its diagonal: shared edge sqrt(2), centroids (2/3, 1/3) and
  // (1/3, 2/3) at distance sqrt(2) / 3, so w = 3.
  Mesh mesh;
  mesh.rest_positions.resize(4, 2);
  mesh.rest_positions << 0, 0, 1, 0, 1, 1, 0, 1;
  mesh.elements.resize(2, 3);
  mesh.elements << 0, 1, 2, 0, 2, 3;
  mesh.element_regions = Eigen::VectorXi::Zero(2);
  const SparseMatrix L = element_adjacency_laplacian(mesh, AdjacencyWeighting::facet_over_distance);
  EXPECT_NEAR(L.coeff(0, 1), -3.0, 1e-14);
  EXPECT_NEAR(L.coeff(0, 0), 3.0, 1e-14);
}

TEST(MaterialModes, SmallBoxMatchesDenseGeneralizedSolve) {
  const Mesh mesh = small_box();
  const int m = mesh.num_elements();
  const SparseMatrix L = element_adjacency_laplacian(mesh);
  // Reference: Eigen's dense GeneralizedSelfAdjointEigenSolver (forward/core/symmetric_eigen).
  Vector exact;
  Matrix dense_vectors;
  ASSERT_TRUE(generalized_symmetric_eigen(Matrix(L), Matrix(volume_matrix(mesh)), exact, dense_vectors));
  // Pick r at a spectral gap, so the span of the first r modes is well defined even where
  // eigenvalues repeat.
  int r = 8;
  while (exact[r] - exact[r - 1] < 1e-6 * exact[r]) ++r;

  MaterialModeOptions options;
  options.eigen.dense_threshold = 0;  // force ARPACK
  const MaterialModes modes = material_modes(mesh, r, options);
  EXPECT_FALSE(modes.solve.dense);
  expect_modes_valid(mesh, modes, AdjacencyWeighting::unit, 1e-9);
  for (int k = 0; k < r; ++k)
    EXPECT_NEAR(modes.eigenvalues[k], exact[k], 1e-8 * std::max(1.0, exact[k])) << "k = " << k;
  // Same subspace: the dense modes are reproduced by V-projection onto ARPACK's.
  const Matrix d = dense_vectors.leftCols(r);
  const Matrix v = Matrix(volume_matrix(mesh));
  const Matrix projected = modes.modes * (modes.modes.transpose() * v * d);
  EXPECT_LT((projected - d).cwiseAbs().maxCoeff(), 1e-8 * d.cwiseAbs().maxCoeff());
  EXPECT_EQ(m, 360);
}

TEST(MaterialModes, FacetOverDistanceModesAreValid) {
  const Mesh mesh = small_box();
  MaterialModeOptions options;
  options.weighting = AdjacencyWeighting::facet_over_distance;
  const MaterialModes modes = material_modes(mesh, 6, options);
  expect_modes_valid(mesh, modes, AdjacencyWeighting::facet_over_distance, 1e-9);
  // Coarse approximation of the Neumann Laplacian of the box [0,1]x[0,1.3]x[0,1.7]: the lowest
  // nonzero eigenvalue is (pi / 1.7)^2 = 3.41; the two-point flux approximation on this
  // coarse Kuhn mesh is only roughly right.
  const double continuum = std::pow(std::numbers::pi / 1.7, 2);
  EXPECT_GT(modes.eigenvalues[1], 0.3 * continuum);
  EXPECT_LT(modes.eigenvalues[1], 3.0 * continuum);
}

TEST(MaterialModes, InvalidInputsThrow) {
  const Mesh mesh = small_box();
  EXPECT_THROW(material_modes(mesh, 0), std::invalid_argument);
  EXPECT_THROW(material_modes(mesh, mesh.num_elements()), std::invalid_argument);
  EXPECT_THROW(material_modes(Mesh{}, 3), std::invalid_argument);
}

TEST(MaterialModes, TwentyModesOn48kTets) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 20, 20, 20);
  ASSERT_EQ(mesh.num_elements(), 48000);
  const auto start = std::chrono::steady_clock::now();
  const MaterialModes modes = material_modes(mesh, 20);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ timing ] 20 material modes on 48000 tets: " << seconds << " s (" << modes.solve.iterations
            << " ARPACK restarts, " << modes.solve.operator_applications << " solves)\n";
  EXPECT_FALSE(modes.solve.dense);
  expect_modes_valid(mesh, modes, AdjacencyWeighting::unit, 1e-8);
}

}  // namespace
}  // namespace tailor::material_modes_test
