// Building damping examples: M-orthonormalization with a clear error for dependent examples,
// eigenmodes (K u = lambda M u) and static responses (K u = f on the free DOFs).
#include "forward/dynamics/damping_examples.hpp"

#include <gtest/gtest.h>

#include "damping_fixture.hpp"

namespace tailor::damping_examples_test {
namespace {

using namespace tailor::testing;

TEST(DampingExamples, MassOrthonormalizeAndRejectDependent) {
  Cantilever c;
  const SparseMatrix M = c.terms.inertia->mass().matrix(c.p);
  const Eigen::Index n = c.model->num_dofs();
  Matrix E(n, 3);
  E.col(0) = random_vector(n, 1, 1.0);
  E.col(1) = random_vector(n, 2, 1.0);
  E.col(2) = random_vector(n, 3, 1.0);
  const Matrix U = mass_orthonormalize(E, M);
  EXPECT_LT((U.transpose() * M * U - Matrix::Identity(3, 3)).norm(), 1e-12);
  E.col(2) = 2.0 * E.col(0) - 0.5 * E.col(1) + 1e-12 * random_vector(n, 4, 1.0);
  try {
    mass_orthonormalize(E, M);
    FAIL() << "a dependent example was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("example 2 is linearly dependent"), std::string::npos) << e.what();
  }
  E.col(2).setZero();
  EXPECT_THROW(mass_orthonormalize(E, M), std::invalid_argument);
}

TEST(DampingExamples, EigenmodesAndStaticResponses) {
  CantileverOptions o;
  o.material = MaterialKind::linear;
  Cantilever c(o);
  const SparseMatrix M = c.terms.inertia->mass().matrix(c.p);
  const SparseMatrix K = c.model->terms()[0]->hessian(c.rest, c.p, HessianMode::exact);
  const SparseMatrix& S = c.model->elimination().basis();
  Vector lambda;
  const Matrix U = eigenmode_examples(K, M, S, {0, 2}, &lambda);
  for (int k = 0; k < 2; ++k) {
    const Vector residual = S.transpose() * (K * U.col(k) - lambda[k] * (M * U.col(k)));
    EXPECT_LT(residual.norm(), 1e-8 * lambda[k] * (S.transpose() * (M * U.col(k))).norm());
  }
  EXPECT_LT(lambda[0], lambda[1]);
  Vector load = Vector::Zero(c.model->num_dofs());
  for (int v : c.tip_vertices) load[3 * v + 2] = 1.0;
  const Matrix u = static_response_examples(K, S, Matrix(load));
  EXPECT_LT((S.transpose() * (K * u.col(0) - load)).norm(), 1e-9 * load.norm());
  EXPECT_GT(u.col(0)[3 * c.tip_vertices[0] + 2], 0.0);  // it bends along the load
}

TEST(DampingExamples, SetupRejectsBadSpecs) {
  Cantilever c;
  ExampleDampingSetup setup;
  DampingExampleSpec s;
  s.source = DampingExampleSpec::Source::displacement;
  s.field = Vector::Zero(5);
  setup.examples = {s};
  EXPECT_THROW(add_example_damping(*c.model, c.mesh, c.terms.inertia->mass_ptr(), c.p, setup),
               std::invalid_argument);
  Cantilever c2;
  s.source = DampingExampleSpec::Source::eigenmode;
  s.mode = -1;
  setup.examples = {s};
  EXPECT_THROW(add_example_damping(*c2.model, c2.mesh, c2.terms.inertia->mass_ptr(), c2.p, setup),
               std::invalid_argument);
}

}  // namespace
}  // namespace tailor::damping_examples_test
