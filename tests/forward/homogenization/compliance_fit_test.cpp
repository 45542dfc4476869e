// The least-squares compliance fit of docs/methods.md section 12.
#include "forward/homogenization/compliance_fit.hpp"

#include <gtest/gtest.h>

#include <random>

#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/linear_homogenization.hpp"

namespace tailor::compliance_fit_test {
namespace {

TEST(ComplianceFit, RecoversAnAnisotropicComplianceExactly) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  Matrix B(6, 6);
  for (auto& v : B.reshaped()) v = n(rng);
  const Matrix C = B * B.transpose() + 6.0 * Matrix::Identity(6, 6);  // any SPD tensor
  std::vector<StressStrainSample> samples;
  for (int i = 0; i < 8; ++i) {
    Vector eps(6);
    for (auto& v : eps) v = n(rng);
    samples.push_back({C * eps, eps});
  }
  EXPECT_LT((fit_compliance(samples) - C.inverse()).norm(), 1e-12 * C.inverse().norm());
  samples.resize(1);  // one direction cannot determine 21 entries
  EXPECT_THROW(fit_compliance(samples), std::invalid_argument);
}

TEST(ComplianceFit, SmallStrainSamplesOfANonlinearCellGiveTheLinearCompliance) {
  // Reference: the linear homogenization of the same cell (small-strain limit).
  const Mesh mesh = lattice_triangle_mesh(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), 8, 8,
                                          TriangleSplit::crossed);
  const int ne = mesh.num_elements();
  Vector E(ne);
  for (int e = 0; e < ne; ++e) E[e] = e % 3 == 0 ? 5.0 : 1.0;
  const Vector nu = Vector::Constant(ne, 0.3);
  LinearCell linear(make_box_periodic_cell(mesh));
  const Matrix S_linear = compliance(linear.solve(E, nu).stiffness);
  NonlinearCell cell(make_box_periodic_cell(mesh), MaterialKind::neo_hookean, E, nu);
  std::vector<StressStrainSample> samples;
  const double t = 1e-5;
  for (const double theta : {0.0, 0.7, 1.4, 2.1, 2.8}) {
    Matrix H(2, 2);
    H << std::cos(theta), 0.5 * std::sin(2 * theta), 0.5 * std::sin(2 * theta), std::sin(theta);
    samples.push_back(macro_sample(cell.solve(Matrix::Identity(2, 2) + t * H)));
  }
  EXPECT_LT((fit_compliance(samples) - S_linear).norm(), 1e-4 * S_linear.norm());
}

}  // namespace
}  // namespace tailor::compliance_fit_test
