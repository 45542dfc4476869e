// Cubature for subspace forces (forward/reduction/cubature.hpp, cubature_design_model.hpp,
// subspace_elements.hpp): derivative checks of the cubature design model (and that they catch
// a derivative 0.1% off), the rule of every element at weight 1 against the projected full
// model, and a fitted StVK rule against the exact polynomial coefficients.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "adjoint/derivative_check.hpp"
#include "forward/reduction/cubature.hpp"
#include "forward/reduction/cubature_design_model.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/polynomial_design_model.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "reduction_fixtures.hpp"

namespace tailor::cubature_test {
namespace {

using namespace tailor::testing;

Matrix modes_of(const ElasticBody& body, int count) {
  ModalAnalysisOptions options;
  options.count = count;
  return mass_orthonormal_basis(modal_analysis(*body.model, body.dim(), body.rest, body.p, body.mass, options).modes,
                                body.mass);
}

// Smooth material modes y_j(x) of the element centroids (y_0 uniform, then linear and
// quadratic in x), like the Laplacian modes the design loop uses.
Matrix smooth_modes(const Mesh& mesh) {
  Matrix y(mesh.num_elements(), 3);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    double x = 0.0;
    for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) x += mesh.rest_positions(mesh.elements(e, a), 0);
    x /= static_cast<double>(mesh.elements.cols());
    y(e, 0) = 1.0;
    y(e, 1) = x / 4.0 - 0.5;
    y(e, 2) = (x / 4.0) * (x / 4.0) - 1.0 / 3.0;
  }
  return y;
}

Vector pose(const Matrix& basis, double size, unsigned seed) {
  std::srand(seed);
  const Vector q = Vector::Random(basis.cols());
  return q * size / (basis * q).cwiseAbs().maxCoeff();
}

Vector parameters_at(const ElasticBody& body, const Matrix& y, const Vector& w) {
  Vector p = body.p;
  const Eigen::Index ne = body.mesh.num_elements();
  p.head(ne) = body.p.head(ne).cwiseProduct(Vector::Ones(ne) + y * w);
  return p;
}

// The derivative checks of a design model at (q, w): force = dW/dq, stiffness = d force/dq,
// d force/dw and its transpose product; `scale` multiplies the analytic derivatives (1.001:
// the checks must fail).
bool derivatives_pass(const ReducedDesignModel& model, const Vector& q, const Vector& w, double scale) {
  DerivativeCheckOptions options;
  options.initial_step = 1e-2;
  const Vector dq = Vector::Random(q.size()) * q.norm();
  const Vector dw = 0.3 * Vector::Random(w.size());
  const auto energy = [&](const Vector& x, const Vector& v) {
    double e = 0.0;
    model.evaluate(x, v, &e, nullptr, nullptr);
    return e;
  };
  const auto force = [&](const Vector& x, const Vector& v) {
    Vector f;
    model.evaluate(x, v, nullptr, &f, nullptr);
    return f;
  };
  Matrix k;
  model.evaluate(q, w, nullptr, nullptr, &k);
  const Vector lambda = Vector::Random(q.size());
  const std::vector<DerivativeCheck> checks{
      check_directional_derivative(
          "force", [&](double t) { return Vector::Constant(1, energy(q + t * dq, w)); },
          Vector::Constant(1, scale * force(q, w).dot(dq)), options),
      check_directional_derivative(
          "stiffness", [&](double t) { return force(q + t * dq, w); }, Vector(scale * (k * dq)), options),
      check_directional_derivative(
          "force_design_derivative", [&](double t) { return force(q, w + t * dw); },
          Vector(scale * (model.force_design_derivative(q) * dw)), options),
      check_directional_derivative(
          "force_design_derivative_transpose",
          [&](double t) { return Vector::Constant(1, lambda.dot(force(q, w + t * dw))); },
          Vector::Constant(1, scale * model.force_design_derivative_transpose(q, lambda).dot(dw)), options)};
  bool all = true;
  for (const DerivativeCheck& c : checks) {
    if (scale == 1.0) {
      EXPECT_TRUE(c.passed) << c.quantity << ": " << c.message;
    }
    all = all && c.passed;
  }
  return all;
}

TEST(CubatureDesignModel, DerivativesPassTheCheckAndCatchAScaledOne) {
  for (MaterialKind kind : {MaterialKind::neo_hookean, MaterialKind::corotated}) {
    const ElasticBody body =
        elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(4, 1, 1), kind, true);
    const Matrix basis = modes_of(body, 6);
    const Matrix y = smooth_modes(body.mesh);
    // A rule of a few elements with uneven weights.
    std::vector<int> chosen{0, 3, 7, 12, 20};
    Vector weights(5);
    weights << 2.0, 0.5, 3.0, 1.25, 4.0;
    const CubatureDesignModel model(SubspaceElements(*body.model, body.p, basis, chosen), weights, y);
    std::srand(2);
    const Vector w = 0.3 * Vector::Random(3);
    const Vector q = pose(basis, 0.4, 5);
    EXPECT_TRUE(derivatives_pass(model, q, w, 1.0)) << to_string(kind);
    EXPECT_FALSE(derivatives_pass(model, q, w, 1.001)) << to_string(kind);
  }
}

// Reference: the definition, W(q; w) = E(x_rest + Phi q, p(w)) summed over every element
// (ProjectedReducedModel, the model's own elastic term); the rule of every element at weight
// 1 must equal it to round-off, for Neo-Hookean in 3D and in plane strain.
TEST(CubatureDesignModel, EveryElementAtWeightOneIsTheProjectedModel) {
  for (int dim : {3, 2}) {
    const ElasticBody body =
        dim == 3 ? elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(6, 2, 2), MaterialKind::neo_hookean, true)
                 : elastic_body(Eigen::Vector2d(4, 1), Eigen::Vector2i(12, 3), MaterialKind::neo_hookean, true);
    const Matrix basis = modes_of(body, 6);
    const Matrix y = smooth_modes(body.mesh);
    SubspaceElements all(*body.model, body.p, basis);
    const int n = all.size();
    ASSERT_EQ(n, body.mesh.num_elements());
    const CubatureDesignModel model(std::move(all), Vector::Ones(n), y);
    Vector w(3);
    w << -0.3, 0.4, 0.2;
    const ProjectedReducedModel projected(*body.model, parameters_at(body, y, w), body.rest, basis);
    for (double size : {0.05, 0.5}) {
      const Vector q = pose(basis, size, 9);
      double e_cub = 0.0, e_ref = 0.0;
      Vector f_cub, f_ref;
      Matrix k_cub, k_ref;
      model.evaluate(q, w, &e_cub, &f_cub, &k_cub);
      projected.evaluate(q, &e_ref, &f_ref, &k_ref);
      EXPECT_NEAR(e_cub, e_ref, 1e-12 * std::abs(e_ref)) << dim << "D";
      EXPECT_LT((f_cub - f_ref).norm(), 1e-12 * f_ref.norm()) << dim << "D";
      EXPECT_LT((k_cub - k_ref).norm(), 1e-12 * k_ref.norm()) << dim << "D";
    }
  }
}

// Reference: the exact polynomial coefficients of reduced StVK (Barbic & James 2005, checked
// against the projected model in reduced_stvk_test). A greedy NNLS rule of at most 60 of the
// 144 elements, fitted on 12 poses over the base and both modes, reproduces the polynomial's
// reduced forces at those poses, for designs w, to the order of the training tolerance.
TEST(Cubature, StvkRuleReproducesThePolynomialForces) {
  const ElasticBody body =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(6, 2, 2), MaterialKind::stvk, true);
  const Matrix basis = modes_of(body, 6);
  const Matrix y = smooth_modes(body.mesh).rightCols(2);
  const int ne = body.mesh.num_elements();
  Matrix weights(ne, 3);
  weights << Vector::Ones(ne), y;
  std::vector<Matrix> g = reduced_stvk_coefficients(*body.model, body.p, basis, weights);
  const Matrix g0 = g[0];
  const PolynomialDesignModel exact(g0, {g[1], g[2]}, static_cast<int>(basis.cols()));
  const SubspaceElements all(*body.model, body.p, basis);
  std::vector<Vector> poses;
  for (unsigned k = 0; k < 12; ++k) poses.push_back(pose(basis, 0.05 + 0.05 * k, 20 + k));
  const CubatureTraining training = cubature_training(all, poses, weights);
  EXPECT_EQ(training.poses, 12);
  CubatureOptions options;
  options.max_elements = 60;
  options.tolerance = 1e-3;
  const CubatureRule rule = fit_cubature(training.a, training.b, options);
  std::printf("StVK rule: %zu of %d elements, training error %.2e after %d steps\n", rule.elements.size(), ne,
              rule.training_error, rule.steps);
  EXPECT_LE(rule.training_error, 1e-3);
  EXPECT_LE(static_cast<int>(rule.elements.size()), 60);
  EXPECT_TRUE((rule.weights.array() > 0.0).all());
  const CubatureDesignModel cubature(SubspaceElements(*body.model, body.p, basis, rule.elements), rule.weights, y);
  double worst = 0.0;
  for (const Vector& w : {Vector(Vector::Zero(2)), Vector(Eigen::Vector2d(-0.4, 0.3)), Vector(Eigen::Vector2d(0.5, -0.5))})
    for (const Vector& q : poses) {
      Vector f_exact, f_cub;
      exact.evaluate(q, w, nullptr, &f_exact, nullptr);
      cubature.evaluate(q, w, nullptr, &f_cub, nullptr);
      worst = std::max(worst, (f_cub - f_exact).norm() / f_exact.norm());
    }
  std::printf("  largest relative force error over the poses and 3 designs: %.2e\n", worst);
  EXPECT_LT(worst, 5e-3);  // 5 x the training tolerance
  // Fewer elements: the error is larger (the check is not trivially met).
  options.max_elements = 3;
  const CubatureRule small = fit_cubature(training.a, training.b, options);
  EXPECT_GT(small.training_error, 1e-2);
}

TEST(Cubature, RandomCandidateSubsetsReachTheTolerance) {
  // An, Kim & James (2008) score a random subset of the elements in each greedy step. With
  // 20 elements per step the fit still reaches the training tolerance, with a rule of
  // about the size of the every-element fit; the same seed gives the same rule, and scoring
  // every element gives the rule of the default options.
  const ElasticBody body =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(4, 2, 2), MaterialKind::neo_hookean, true);
  const Matrix basis = modes_of(body, 6);
  const int ne = body.mesh.num_elements();
  const SubspaceElements all(*body.model, body.p, basis);
  std::vector<Vector> poses;
  for (unsigned k = 0; k < 10; ++k) poses.push_back(pose(basis, 0.05 + 0.05 * k, 40 + k));
  const CubatureTraining training = cubature_training(all, poses, Matrix::Ones(ne, 1));
  CubatureOptions every;
  every.max_elements = 60;
  const CubatureRule reference = fit_cubature(training.a, training.b, every);
  CubatureOptions subsets = every;
  subsets.candidates = 20;
  const CubatureRule rule = fit_cubature(training.a, training.b, subsets);
  std::printf("Neo-Hookean rule on %d elements: %zu elements (error %.2e) scoring every element, %zu (error %.2e) "
              "scoring 20 per step\n",
              ne, reference.elements.size(), reference.training_error, rule.elements.size(), rule.training_error);
  EXPECT_LE(reference.training_error, every.tolerance);
  EXPECT_LE(rule.training_error, subsets.tolerance);
  EXPECT_LE(rule.elements.size(), 2 * reference.elements.size());
  EXPECT_NE(rule.elements, reference.elements);  // the subsets did change the path
  const CubatureRule again = fit_cubature(training.a, training.b, subsets);
  EXPECT_EQ(again.elements, rule.elements);
  subsets.candidates = ne;  // at least every element: the default fit
  EXPECT_EQ(fit_cubature(training.a, training.b, subsets).elements, reference.elements);
  subsets.candidates = -1;
  EXPECT_THROW(fit_cubature(training.a, training.b, subsets), std::invalid_argument);
}

TEST(Cubature, BadInputIsAClearError) {
  CubatureOptions options;
  options.max_elements = 0;
  EXPECT_THROW(fit_cubature(Matrix::Identity(3, 3), Vector::Ones(3), options), std::invalid_argument);
  options.max_elements = 2;
  options.tolerance = 0.0;
  EXPECT_THROW(fit_cubature(Matrix::Identity(3, 3), Vector::Ones(3), options), std::invalid_argument);
  options.tolerance = 1e-3;
  EXPECT_THROW(fit_cubature(Matrix::Identity(3, 3), Vector::Zero(3), options), std::invalid_argument);
  const ElasticBody body =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(2, 1, 1), MaterialKind::neo_hookean, true);
  const Matrix basis = modes_of(body, 2);
  EXPECT_THROW(CubatureDesignModel(SubspaceElements(*body.model, body.p, basis, {0}), -Vector::Ones(1),
                                   smooth_modes(body.mesh)),
               std::invalid_argument);
  EXPECT_THROW(SubspaceElements(*body.model, body.p, Matrix::Zero(3, 2)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::cubature_test
