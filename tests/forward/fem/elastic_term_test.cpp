// Derivative checks of the FEM elastic energy for every material, in 3D and plane strain,
// on random, rotated, nearly incompressible, nearly inverted and inverted states; the patch
// test; and rotation invariance of the nonlinear materials.
#include "forward/fem/elastic_term.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../../support/fem_fixtures.hpp"
#include "adjoint/derivative_check.hpp"
#include "forward/core/elimination.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::elastic_term_test {
namespace {

using namespace tailor::testing;

struct Case {
  MaterialKind material;
  int dim;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return to_string(info.param.material) + "_" + std::to_string(info.param.dim) + "d";
}

class ElasticTermTest : public ::testing::TestWithParam<Case> {
 protected:
  template <int Dim>
  void check_state(const Mesh& mesh, const Vector& x, double poisson, const std::string& label,
                   HessianMode mode) {
    const auto term = elastic_term<Dim>(mesh, GetParam().material);
    const Vector p = heterogeneous_parameters(mesh, 1e3, poisson);
    DerivativeCheckOptions options;
    options.initial_step = 1e-4;
    options.tolerance = 2e-6;
    options.hessian_mode = mode;
    const EnergyTermCheck c = check_energy_term(*term, x, p, options);
    EXPECT_TRUE(c.passed()) << label << "\n" << c.table();
  }

  template <int Dim>
  void run_all_states() {
    const Mesh mesh = small_mesh(Dim);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vector noise(Dim * mesh.num_vertices());
    for (auto& v : noise) v = u(rng);
    const Vector rest = rest_state(mesh);
    const Matrix I = Matrix::Identity(Dim, Dim);
    Matrix G = Matrix::Zero(Dim, Dim);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) G(i, j) = u(rng);

    check_state<Dim>(mesh, rest + 0.05 * noise, 0.3, "small random", HessianMode::exact);
    check_state<Dim>(mesh, rest + 0.3 * noise, 0.3, "large random", HessianMode::exact);
    check_state<Dim>(
        mesh, affine_state(mesh, rotation(Dim, 1.5708) * (I + 0.2 * G), Vector::Ones(Dim)) + 0.02 * noise,
        0.3, "large rotation", HessianMode::exact);
    check_state<Dim>(mesh, rest + 0.05 * noise, 0.49, "nu = 0.49", HessianMode::exact);
    check_state<Dim>(mesh, rest + 0.05 * noise, 0.4999, "nu = 0.4999", HessianMode::exact);
    // Nearly flattened: every element compressed along the first axis to 2% of its height.
    Matrix squash = I;
    squash(0, 0) = 0.02;
    check_state<Dim>(mesh, affine_state(mesh, squash, Vector::Zero(Dim)) + 0.002 * noise, 0.3,
                     "nearly inverted", HessianMode::exact);
    const MaterialKind kind = GetParam().material;
    if (kind == MaterialKind::neo_hookean || kind == MaterialKind::corotated) {
      // Inverted: a reflection of the whole mesh composed with a mild stretch.
      Matrix flip = I + 0.1 * G;
      flip.row(0) *= -1.0;
      check_state<Dim>(mesh, affine_state(mesh, flip, Vector::Zero(Dim)) + 0.01 * noise, 0.3, "inverted",
                       HessianMode::exact);
    }
  }
};

TEST_P(ElasticTermTest, DerivativesMatchDifferences) {
  if (GetParam().dim == 3)
    run_all_states<3>();
  else
    run_all_states<2>();
}

// The projected Hessian is positive semidefinite and equals the exact one at rest.
TEST_P(ElasticTermTest, ProjectedHessianIsPositiveSemidefinite) {
  auto check = [&]<int Dim>() {
    const Mesh mesh = small_mesh(Dim);
    const auto term = elastic_term<Dim>(mesh, GetParam().material);
    const Vector p = heterogeneous_parameters(mesh, 1e3, 0.3);
    Matrix squash = Matrix::Identity(Dim, Dim);
    squash(0, 0) = 0.3;  // strong compression makes several materials indefinite
    const Vector x = affine_state(mesh, squash, Vector::Zero(Dim));
    const Matrix H = Matrix(term->hessian(x, p, HessianMode::projected));
    const double min_eig = symmetric_eigenvalues(H).minCoeff();
    EXPECT_GE(min_eig, -1e-9 * H.norm());
    const Vector rest = rest_state(mesh);
    const Matrix exact = Matrix(term->hessian(rest, p, HessianMode::exact));
    const Matrix projected = Matrix(term->hessian(rest, p, HessianMode::projected));
    EXPECT_LT((exact - projected).norm(), 1e-9 * exact.norm());
  };
  if (GetParam().dim == 3)
    check.template operator()<3>();
  else
    check.template operator()<2>();
}

// Patch test: with an affine displacement prescribed on the boundary, Newton reproduces the
// affine field in the interior to round-off (any homogeneous deformation of a homogeneous
// body is an equilibrium without body forces).
TEST_P(ElasticTermTest, PatchTestReproducesAffineField) {
  auto run = [&]<int Dim>() {
    const Mesh mesh = Dim == 3 ? box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 3, 3, 3)
                               : rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 4, 4);
    Model model(Dim * mesh.num_vertices());
    const int m = mesh.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<Dim>(mesh, GetParam().material));
    Vector p(2 * m);
    p.head(m).setConstant(1e3);
    p.tail(m).setConstant(0.3);

    Matrix A = Matrix::Identity(Dim, Dim);
    A(0, 0) = 1.05;
    A(0, 1) = 0.03;
    A(Dim - 1, 0) = -0.02;
    const Vector c = Vector::Constant(Dim, 0.1);
    const Vector target = affine_state(mesh, A, c);
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const auto X = mesh.rest_positions.row(v);
      if ((X.array() < 1e-12).any() || (X.array() > 1.0 - 1e-12).any())
        for (int k = 0; k < Dim; ++k) fixed.push_back(Dim * v + k);
    }
    model.set_elimination(Elimination::dirichlet(fixed, target));
    ASSERT_LT(static_cast<int>(fixed.size()), model.num_dofs()) << "the patch needs interior vertices";
    NewtonSolver solver(model);
    Vector y = model.elimination().restrict_state(rest_state(mesh));
    const NewtonResult r = solver.solve(p, y);
    ASSERT_TRUE(r.converged()) << r.report();
    const Vector x = model.elimination().expand(y);
    EXPECT_LT((x - target).lpNorm<Eigen::Infinity>(), 1e-10);
  };
  if (GetParam().dim == 3)
    run.template operator()<3>();
  else
    run.template operator()<2>();
}

// Rotation invariance: zero energy and zero force under a rigid rotation of 90 degrees for
// every nonlinear material.
TEST_P(ElasticTermTest, RigidRotationIsStressFree) {
  auto run = [&]<int Dim>() {
    const Mesh mesh = small_mesh(Dim);
    const auto term = elastic_term<Dim>(mesh, GetParam().material);
    const Vector p = heterogeneous_parameters(mesh, 1e3, 0.3);
    const Vector x = affine_state(mesh, rotation(Dim, M_PI / 2), Vector::Constant(Dim, 2.0));
    if (GetParam().material == MaterialKind::linear) {
      // Linear elasticity is not rotation invariant: it sees a strain of order one.
      EXPECT_GT(term->value(x, p), 1.0);
      return;
    }
    Vector g = Vector::Zero(x.size());
    term->add_gradient(x, p, g);
    // Scale of forces: stiffness times size; round-off relative to that.
    EXPECT_LT(std::abs(term->value(x, p)), 1e-10 * 1e3);
    EXPECT_LT(g.lpNorm<Eigen::Infinity>(), 1e-10 * 1e3);
  };
  if (GetParam().dim == 3)
    run.template operator()<3>();
  else
    run.template operator()<2>();
}

INSTANTIATE_TEST_SUITE_P(AllMaterials, ElasticTermTest,
                         ::testing::Values(Case{MaterialKind::linear, 3}, Case{MaterialKind::corotated, 3},
                                           Case{MaterialKind::stvk, 3}, Case{MaterialKind::neo_hookean, 3},
                                           Case{MaterialKind::linear, 2}, Case{MaterialKind::corotated, 2},
                                           Case{MaterialKind::stvk, 2}, Case{MaterialKind::neo_hookean, 2}),
                         case_name);

}  // namespace
}  // namespace tailor::elastic_term_test
