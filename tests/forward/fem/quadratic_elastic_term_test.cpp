// The quadratic (P2) elastic term: derivative checks (gradient, Hessian, dE/dp, the mixed block
// and its transpose product) for every registered material in 3D and plane strain, the
// projected Hessian, the patch test (a linear displacement reproduced exactly by Newton with
// only the boundary prescribed), exact integration of quadratic fields, and the consistent
// loads of forward/fem/quadratic_loads.hpp.
#include "forward/fem/quadratic_elastic_term.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "adjoint/derivative_check.hpp"
#include "forward/core/elimination.hpp"
#include "forward/core/model.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/fem/material_registry.hpp"
#include "forward/fem/quadratic_loads.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/solve/newton.hpp"
#include "../../support/fem_fixtures.hpp"

namespace tailor::quadratic_elastic_term_test {
namespace {

using namespace tailor::testing;

QuadraticMesh small_quadratic_mesh(int dim) {
  if (dim == 3) return make_quadratic_mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 1, 1, 1));
  return make_quadratic_mesh(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 2, 1));
}

// x_v = A X_v + c at every node.
Vector affine_nodes(const QuadraticMesh& q, const Matrix& A, const Vector& c) {
  const int dim = q.dim();
  Vector x(dim * q.num_nodes());
  for (int v = 0; v < q.num_nodes(); ++v) x.segment(dim * v, dim) = A * q.rest_positions.row(v).transpose() + c;
  return x;
}

template <int Dim>
std::unique_ptr<QuadraticElasticTerm<Dim>> quadratic_term(const QuadraticMesh& q, const std::string& material) {
  return std::make_unique<QuadraticElasticTerm<Dim>>(q, make_material<Dim>(parse_material_kind(material)), 0,
                                                     q.num_elements());
}

struct Case {
  std::string material;
  int dim;
};

std::vector<Case> every_material() {
  std::vector<Case> cases;
  for (int dim : {3, 2})
    for (const std::string& name : material_names()) cases.push_back({name, dim});
  return cases;
}

class QuadraticElasticTermTest : public ::testing::TestWithParam<Case> {
 protected:
  template <int Dim>
  void check_state(const QuadraticMesh& q, const Vector& x, double poisson, const std::string& label) {
    const auto term = quadratic_term<Dim>(q, GetParam().material);
    const Vector p = heterogeneous_parameters(q.corners, 1e3, poisson);
    DerivativeCheckOptions options;
    options.initial_step = 1e-4;
    options.tolerance = 2e-6;
    const EnergyTermCheck c = check_energy_term(*term, x, p, options);
    EXPECT_TRUE(c.passed()) << label << "\n" << c.table();
    std::set<std::string> checked;
    for (const auto& one : c.checks) checked.insert(one.quantity);
    for (const char* quantity : {"gradient", "hessian", "param_gradient", "mixed", "mixed_transpose"})
      EXPECT_TRUE(checked.count(quantity)) << quantity << " was not checked";
  }

  template <int Dim>
  void run_all_states() {
    const QuadraticMesh q = small_quadratic_mesh(Dim);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vector noise(Dim * q.num_nodes());
    for (auto& v : noise) v = u(rng);
    const Vector rest = quadratic_rest_state(q);
    Matrix G = Matrix::Zero(Dim, Dim);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) G(i, j) = u(rng);
    check_state<Dim>(q, rest + 0.05 * noise, 0.3, "small random");
    check_state<Dim>(q, rest + 0.15 * noise, 0.3, "large random");
    check_state<Dim>(q, affine_nodes(q, rotation(Dim, 1.5708) * (Matrix::Identity(Dim, Dim) + 0.2 * G), Vector::Ones(Dim)) + 0.02 * noise,
                     0.3, "large rotation");
    check_state<Dim>(q, rest + 0.05 * noise, 0.4999, "nu = 0.4999");
  }
};

TEST_P(QuadraticElasticTermTest, DerivativesMatchDifferences) {
  if (GetParam().dim == 3)
    run_all_states<3>();
  else
    run_all_states<2>();
}

// The projected Hessian is positive semidefinite and equals the exact one at rest.
TEST_P(QuadraticElasticTermTest, ProjectedHessianIsPositiveSemidefinite) {
  auto check = [&]<int Dim>() {
    const QuadraticMesh q = small_quadratic_mesh(Dim);
    const auto term = quadratic_term<Dim>(q, GetParam().material);
    const Vector p = heterogeneous_parameters(q.corners, 1e3, 0.3);
    Matrix squash = Matrix::Identity(Dim, Dim);
    squash(0, 0) = 0.3;
    const Matrix H = Matrix(term->hessian(affine_nodes(q, squash, Vector::Zero(Dim)), p, HessianMode::projected));
    EXPECT_GE(symmetric_eigenvalues(H).minCoeff(), -1e-9 * H.norm());
    const Vector rest = quadratic_rest_state(q);
    const Matrix exact = Matrix(term->hessian(rest, p, HessianMode::exact));
    const Matrix projected = Matrix(term->hessian(rest, p, HessianMode::projected));
    EXPECT_LT((exact - projected).norm(), 1e-9 * exact.norm());
  };
  if (GetParam().dim == 3)
    check.template operator()<3>();
  else
    check.template operator()<2>();
}

// Patch test: an affine deformation prescribed on every boundary node (corner and edge nodes)
// is reproduced at the interior nodes to round-off, for every material.
TEST_P(QuadraticElasticTermTest, PatchTestReproducesAffineField) {
  auto run = [&]<int Dim>() {
    const QuadraticMesh q =
        Dim == 3 ? make_quadratic_mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 2, 2, 2))
                 : make_quadratic_mesh(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 3, 3));
    Model model(Dim * q.num_nodes());
    const int m = q.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(quadratic_term<Dim>(q, GetParam().material));
    Vector p(2 * m);
    p.head(m).setConstant(1e3);
    p.tail(m).setConstant(0.3);
    Matrix A = Matrix::Identity(Dim, Dim);
    A(0, 0) = 1.05;
    A(0, 1) = 0.03;
    A(Dim - 1, 0) = -0.02;
    const Vector target = affine_nodes(q, A, Vector::Constant(Dim, 0.1));
    const std::vector<int> boundary = nodes_where(q, [](const Eigen::VectorXd& X) {
      return (X.array() < 1e-12).any() || (X.array() > 1.0 - 1e-12).any();
    });
    const std::vector<int> fixed = node_dofs(q, boundary);
    model.set_elimination(Elimination::dirichlet(fixed, target));
    ASSERT_LT(static_cast<int>(fixed.size()), model.num_dofs());
    NewtonOptions options;
    options.relative_tolerance = 1e-13;  // the check is at round-off
    NewtonSolver solver(model, options);
    Vector y = model.elimination().restrict_state(quadratic_rest_state(q));
    const NewtonResult r = solver.solve(p, y);
    ASSERT_TRUE(r.converged()) << r.report();
    EXPECT_LT((model.elimination().expand(y) - target).lpNorm<Eigen::Infinity>(), 1e-10);
  };
  if (GetParam().dim == 3)
    run.template operator()<3>();
  else
    run.template operator()<2>();
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return info.param.material + "_" + std::to_string(info.param.dim) + "d";
}

INSTANTIATE_TEST_SUITE_P(EveryRegisteredMaterial, QuadraticElasticTermTest, ::testing::ValuesIn(every_material()),
                         case_name);

// The degree-2 rule integrates the linear material's energy of a quadratic displacement exactly
// (a quadratic integrand on straight-sided elements): u = (c x y, 0[, 0]) on the unit square or
// cube has eps = [[c y, c x / 2], [c x / 2, 0]], so
//   E = int mu (c^2 y^2 + c^2 x^2 / 2) + lambda / 2 c^2 y^2 = c^2 (mu / 2 + lambda / 6).
// Linear elements cannot represent u; quadratic ones interpolate it exactly.
TEST(QuadraticElasticTerm, IntegratesQuadraticFieldsExactly) {
  const double c = 0.3, E = 200.0, nu = 0.35;
  const LameParameters lame = lame_from_young_poisson(E, nu);
  const double expected = c * c * (lame.mu / 2 + lame.lambda / 6);
  auto energy = [&]<int Dim>(const QuadraticMesh& q) {
    Vector x = quadratic_rest_state(q);
    for (int v = 0; v < q.num_nodes(); ++v) x[Dim * v] += c * q.rest_positions(v, 0) * q.rest_positions(v, 1);
    const int m = q.num_elements();
    Vector p(2 * m);
    p.head(m).setConstant(E);
    p.tail(m).setConstant(nu);
    return quadratic_term<Dim>(q, "linear")->value(x, p);
  };
  const QuadraticMesh square =
      make_quadratic_mesh(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 3, 2));
  const QuadraticMesh cube = make_quadratic_mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 2, 1, 2));
  EXPECT_NEAR(energy.template operator()<2>(square), expected, 1e-13 * expected);
  EXPECT_NEAR(energy.template operator()<3>(cube), expected, 1e-13 * expected);
}

// Splitting by elements (forward/solve/hessian_share.hpp): the shares of a partition of the
// elements sum to the whole term, and a share keeps the element's full 10-node DOF list.
TEST(QuadraticElasticTerm, SharesByElementsSumToTheWhole) {
  const QuadraticMesh q = small_quadratic_mesh(3);
  const auto term = quadratic_term<3>(q, "neo_hookean");
  const Vector p = heterogeneous_parameters(q.corners, 1e3, 0.3);
  Vector x = quadratic_rest_state(q);
  for (int i = 0; i < x.size(); ++i) x[i] += 0.01 * std::sin(1.0 + i);
  double sum = 0.0;
  for (bool first : {true, false}) {
    std::unique_ptr<EnergyTerm> share;
    ASSERT_TRUE(term->share_by_elements(
        [&](const int* dofs, int count) {
          EXPECT_EQ(count, 30);
          return (dofs[0] % 2 == 0) == first;
        },
        share));
    if (share) sum += share->value(x, p);
  }
  EXPECT_NEAR(sum, term->value(x, p), 1e-12 * std::abs(term->value(x, p)));
}

// The total force of a nodal force vector.
Vector component_sums(const Vector& f, int dim) {
  return Eigen::Map<const Matrix>(f.data(), dim, f.size() / dim).rowwise().sum();
}

// Consistent loads: the weights of a straight edge (1/6, 1/6, 2/3), of a flat triangle (0 at the
// corners, 1/3 at the edges) and of a tet (-1/20, 1/5); pressure on a closed boundary has zero
// total force, and on a face it is -p n A.
TEST(QuadraticLoads, ConsistentNodalWeights) {
  const QuadraticMesh square =
      make_quadratic_mesh(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 1, 1));
  const Eigen::MatrixXi right = quadratic_facets(
      square, boundary_facets_where(square.corners, [](const Eigen::VectorXd& X) { return X[0] > 2 - 1e-12; }));
  ASSERT_EQ(right.rows(), 1);
  const Vector f = quadratic_traction_forces(square, right, Eigen::Vector2d(0, 6));
  EXPECT_NEAR(f[2 * right(0, 0) + 1], 1.0, 1e-14);
  EXPECT_NEAR(f[2 * right(0, 1) + 1], 1.0, 1e-14);
  EXPECT_NEAR(f[2 * right(0, 2) + 1], 4.0, 1e-14);
  const Vector pressure = quadratic_pressure_forces(square, right, 3.0);  // pushes along -x
  EXPECT_NEAR(pressure.sum(), -3.0, 1e-14);
  EXPECT_NEAR(pressure[2 * right(0, 2)], -2.0, 1e-14);
  const Eigen::MatrixXi all = quadratic_facets(square, boundary_facets(square.corners));
  EXPECT_LT(component_sums(quadratic_pressure_forces(square, all, 3.0), 2).norm(), 1e-13);

  const QuadraticMesh cube = make_quadratic_mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 1), 1, 1, 1));
  const Eigen::MatrixXi top = quadratic_facets(
      cube, boundary_facets_where(cube.corners, [](const Eigen::VectorXd& X) { return X[2] > 1 - 1e-12; }));
  const Vector t = quadratic_traction_forces(cube, top, Eigen::Vector3d(0, 0, 1));
  EXPECT_NEAR(t.sum(), 2.0, 1e-13);  // area 2
  for (int k = 0; k < top.rows(); ++k) EXPECT_NEAR(t[3 * top(k, 0) + 2], 0.0, 1e-14);
  const Vector closed = quadratic_pressure_forces(cube, quadratic_facets(cube, boundary_facets(cube.corners)), 5.0);
  EXPECT_LT(component_sums(closed, 3).norm(), 1e-13);

  const Vector g = quadratic_gravity_forces(cube, Eigen::VectorXd::Constant(cube.num_elements(), 2.0),
                                            Eigen::Vector3d(0, 0, -1));
  EXPECT_NEAR(g.sum(), -4.0, 1e-13);  // mass 2 * volume 2
  const Eigen::VectorXd volumes = element_volumes(cube.corners);
  double corner0 = 0.0;
  for (int e = 0; e < cube.num_elements(); ++e)
    for (int a = 0; a < 4; ++a)
      if (cube.elements(e, a) == 0) corner0 += 2.0 * volumes[e] * (1.0 / 20.0);
  EXPECT_NEAR(g[2], corner0, 1e-14);  // -(-1/20) rho V g per element
}

}  // namespace
}  // namespace tailor::quadratic_elastic_term_test
