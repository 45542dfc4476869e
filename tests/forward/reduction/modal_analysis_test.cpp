// Modal analysis: a clamped cantilever against beam theory, a free block's rigid modes, and
// mass-orthonormality.
#include "forward/reduction/modal_analysis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "reduction_fixtures.hpp"

namespace tailor::modal_analysis_test {
namespace {

using namespace tailor::testing;

// Euler-Bernoulli cantilever (clamped-free): omega_n = (beta_n L)^2 sqrt(E I / (rho A L^4)),
// beta_1 L = 1.875104, beta_2 L = 4.694091 (roots of cos(bL) cosh(bL) = -1). The beam is
// slender (L / h = 20), so Timoshenko's shear and rotary-inertia corrections are small (they
// lower the frequencies by about 0.3% for mode 1 and 2% for mode 2). Linear simplices lock in
// bending (too stiff: +7% at 4 tets through the height), with an error of second order in the
// mesh size; so the test checks that the error falls about 4x per halving of h and that the
// Richardson extrapolation (4 f_h/2 - f_h) / 3 lies within 3% of Euler-Bernoulli.
double euler_bernoulli_hz(int mode, double length, double height, double youngs, double density) {
  const double beta_l = mode == 1 ? 1.875104068711961 : 4.694091132974174;
  const double i_over_a = height * height / 12.0;
  return beta_l * beta_l * std::sqrt(youngs * i_over_a / (density * std::pow(length, 4))) /
         (2 * std::numbers::pi);
}

constexpr double kLength = 10.0, kHeight = 0.5, kYoung = 1000.0, kDensity = 1.0;

// The lowest `count` frequencies with n elements through the height (nu = 0, as beam theory).
Vector cantilever_frequencies(int dim, int n, int count) {
  const ElasticBody beam =
      dim == 3 ? elastic_body(Eigen::Vector3d(kLength, kHeight, kHeight), Eigen::Vector3i(20 * n, n, n),
                              MaterialKind::linear, true, kYoung, 0.0, kDensity)
               : elastic_body(Eigen::Vector2d(kLength, kHeight), Eigen::Vector2i(20 * n, n),
                              MaterialKind::linear, true, kYoung, 0.0, kDensity);
  ModalAnalysisOptions options;
  options.count = count;
  const ModalAnalysis modes = modal_analysis(*beam.model, dim, beam.rest, beam.p, beam.mass, options);
  EXPECT_EQ(modes.rigid_modes.cols(), 0);
  return modes.frequencies;
}

void check_cantilever(int dim, int n, const std::vector<int>& bending_modes) {
  const int count = bending_modes.back() + 1;
  const Vector coarse = cantilever_frequencies(dim, n, count),
               fine = cantilever_frequencies(dim, 2 * n, count);
  for (std::size_t k = 0; k < bending_modes.size(); ++k) {
    const int j = bending_modes[k];
    const double theory =
        euler_bernoulli_hz(k < bending_modes.size() / 2 ? 1 : 2, kLength, kHeight, kYoung, kDensity);
    const double extrapolated = (4.0 * fine[j] - coarse[j]) / 3.0;
    const double ratio = (coarse[j] - theory) / (fine[j] - theory);
    std::printf(
        "%dD mode %d: f(h) = %.6f, f(h/2) = %.6f, extrapolated %.6f, Euler-Bernoulli %.6f Hz (%+.2f%%), "
        "error ratio %.2f\n",
        dim, j, coarse[j], fine[j], extrapolated, theory, 100 * (extrapolated / theory - 1), ratio);
    EXPECT_GT(fine[j], theory);  // locking: too stiff
    EXPECT_GT(ratio, 3.0);       // second order
    EXPECT_NEAR(extrapolated / theory, 1.0, 0.03);
  }
}

// 3D, square section: two bending directions per order (the Kuhn split is not symmetric in y
// and z, so each pair is split slightly); modes 0-1 first order, 2-3 second order.
TEST(ModalAnalysis, CantileverMatchesBeamTheory3d) { check_cantilever(3, 2, {0, 1, 2, 3}); }
// 2D plane strain with nu = 0 (= plane stress): one bending direction; modes 0 and 1.
TEST(ModalAnalysis, CantileverMatchesBeamTheory2d) { check_cantilever(2, 4, {0, 1}); }

TEST(ModalAnalysis, ModesAreMassOrthonormalAndSolveTheEigenproblem) {
  const ElasticBody beam =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(8, 2, 2), MaterialKind::neo_hookean, true);
  ModalAnalysisOptions options;
  options.count = 6;
  const ModalAnalysis modes = modal_analysis(*beam.model, 3, beam.rest, beam.p, beam.mass, options);
  const Matrix gram = modes.modes.transpose() * (beam.mass * modes.modes);
  EXPECT_LT((gram - Matrix::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-12);
  // Residual K phi - lambda M phi in the free unknowns, relative to |K phi|.
  for (int j = 0; j < 6; ++j) {
    const Vector k_phi = beam.model->hessian_times(beam.rest, beam.p, modes.modes.col(j));
    const Vector r =
        beam.model->elimination().reduce(k_phi - modes.eigenvalues[j] * (beam.mass * modes.modes.col(j)));
    EXPECT_LT(r.norm(), 1e-8 * beam.model->elimination().reduce(k_phi).norm());
  }
  for (int j = 1; j < 6; ++j) EXPECT_GE(modes.eigenvalues[j], modes.eigenvalues[j - 1]);
}

void check_free_body(int dim) {
  const ElasticBody block =
      dim == 3 ? elastic_body(Eigen::Vector3d(3, 1.5, 1), Eigen::Vector3i(6, 3, 2), MaterialKind::stvk, false)
               : elastic_body(Eigen::Vector2d(3, 1.5), Eigen::Vector2i(12, 6), MaterialKind::stvk, false);
  const int k = dim == 3 ? 6 : 3;
  ModalAnalysisOptions options;
  options.count = 5;
  options.rigid = RigidModeHandling::shift;
  const ModalAnalysis shifted = modal_analysis(*block.model, dim, block.rest, block.p, block.mass, options);
  options.rigid = RigidModeHandling::deflate;
  const ModalAnalysis deflated = modal_analysis(*block.model, dim, block.rest, block.p, block.mass, options);

  // Exactly k near-zero modes, set apart; the elastic ones well above them.
  ASSERT_EQ(shifted.rigid_modes.cols(), k);
  ASSERT_EQ(deflated.rigid_modes.cols(), k);
  const double first_elastic = deflated.eigenvalues[0];
  EXPECT_GT(first_elastic, 1e-3);
  EXPECT_LT(shifted.rigid_eigenvalues.cwiseAbs().maxCoeff(), 1e-9 * first_elastic);
  EXPECT_LT(deflated.rigid_eigenvalues.cwiseAbs().maxCoeff(), 1e-9 * first_elastic);
  // The same elastic spectrum and modes either way (up to sign).
  for (int j = 0; j < 5; ++j) {
    EXPECT_NEAR(shifted.eigenvalues[j] / deflated.eigenvalues[j], 1.0, 1e-9) << "mode " << j;
    const double overlap = std::abs(shifted.modes.col(j).dot(block.mass * deflated.modes.col(j)));
    EXPECT_NEAR(overlap, 1.0, 1e-7) << "mode " << j;
  }
  // Rigid and elastic modes together are M-orthonormal, and the two rigid subspaces agree.
  Matrix all(shifted.modes.rows(), k + 5);
  all << deflated.rigid_modes, deflated.modes;
  EXPECT_LT((all.transpose() * (block.mass * all) - Matrix::Identity(k + 5, k + 5)).cwiseAbs().maxCoeff(),
            1e-10);
  const Matrix cross = deflated.rigid_modes.transpose() * (block.mass * shifted.rigid_modes);
  EXPECT_NEAR(cross.squaredNorm(), k, 1e-8);
}

TEST(ModalAnalysis, FreeBlockHasSixRigidModes3d) { check_free_body(3); }
TEST(ModalAnalysis, FreeRectangleHasThreeRigidModes2d) { check_free_body(2); }

TEST(ModalAnalysis, PinnedBodyKeepsOnlyItsRotations) {
  ElasticBody block =
      elastic_body(Eigen::Vector3d(2, 1, 1), Eigen::Vector3i(4, 2, 2), MaterialKind::linear, false);
  block.model->set_elimination(Elimination::dirichlet({0, 1, 2}, block.rest));  // vertex 0 pinned
  ModalAnalysisOptions options;
  options.count = 3;
  const ModalAnalysis modes = modal_analysis(*block.model, 3, block.rest, block.p, block.mass, options);
  EXPECT_EQ(modes.rigid_modes.cols(), 3);
  EXPECT_GT(modes.eigenvalues[0], 1.0);
}

TEST(ModalAnalysis, RejectsBadInput) {
  const ElasticBody beam =
      elastic_body(Eigen::Vector2d(2, 1), Eigen::Vector2i(2, 1), MaterialKind::linear, true);
  ModalAnalysisOptions options;
  options.count = 0;
  EXPECT_THROW(modal_analysis(*beam.model, 2, beam.rest, beam.p, beam.mass, options), std::invalid_argument);
  options.count = 1;
  EXPECT_THROW(modal_analysis(*beam.model, 4, beam.rest, beam.p, beam.mass, options), std::invalid_argument);
  EXPECT_THROW(modal_analysis(*beam.model, 2, Vector::Zero(3), beam.p, beam.mass, options),
               std::invalid_argument);
}

}  // namespace
}  // namespace tailor::modal_analysis_test
