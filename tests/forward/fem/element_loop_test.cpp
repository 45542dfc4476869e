// The shared element loop of ElasticTerm, SplineElasticTerm and QuadraticElasticTerm
// (forward/fem/element_loop.hpp):
//  - every element contributes exactly once: the whole term's energy, gradient and Hessian slots
//    equal the sums of one-element terms (the reference, evaluated one element at a time);
//  - the result does not depend on the thread count (1, 2 or 3 OpenMP threads give the same
//    bits);
//  - evaluate() is re-entrant: two threads evaluating the same term at once get the same bits as
//    a serial evaluation.
// The meshes have more than 256 elements, so the loop runs in parallel.
#include <gtest/gtest.h>
#include <omp.h>

#include <functional>
#include <limits>
#include <stdexcept>
#include <memory>
#include <random>
#include <thread>

#include "forward/fem/elastic_term.hpp"
#include "forward/fem/quadratic_elastic_term.hpp"
#include "forward/fem/spline_elastic_term.hpp"
#include "forward/mesh/generate.hpp"
#include "tests/support/fem_fixtures.hpp"

namespace tailor::element_loop_test {
namespace {

struct Evaluation {
  double value = 0.0;
  Vector gradient;
  std::vector<double> hessian;
};

Evaluation evaluate(const EnergyTerm& term, const Vector& x, const Vector& p) {
  HessianPattern pattern;
  term.hessian_pattern(pattern);
  Evaluation e;
  e.gradient = Vector::Zero(x.size());
  e.hessian.assign(pattern.size(), 0.0);
  EnergyRequest request;
  request.value = &e.value;
  request.gradient = &e.gradient;
  request.hessian_values = e.hessian.data();
  term.evaluate(x, p, request);
  return e;
}

void expect_identical(const Evaluation& a, const Evaluation& b, const std::string& label) {
  EXPECT_EQ(a.value, b.value) << label;
  EXPECT_EQ((a.gradient - b.gradient).lpNorm<Eigen::Infinity>(), 0.0) << label;
  ASSERT_EQ(a.hessian.size(), b.hessian.size()) << label;
  EXPECT_TRUE(a.hessian == b.hessian) << label;
}

Vector perturbed_rest(const Mesh& mesh, double amplitude) {
  Vector x = testing::rest_state(mesh);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (int i = 0; i < x.size(); ++i) x[i] += u(rng);
  return x;
}

// make(elements): the term over those elements (all when empty).
void check_loop(const Mesh& mesh, const Vector& x, const Vector& p,
                const std::function<std::unique_ptr<EnergyTerm>(std::vector<int>)>& make) {
  ASSERT_GT(mesh.num_elements(), 256) << "the mesh must be large enough for the parallel loop";
  const std::unique_ptr<EnergyTerm> term = make({});
  const int saved_threads = omp_get_max_threads();

  // Reference: one element at a time, the contributions summed in element order.
  Evaluation reference;
  reference.gradient = Vector::Zero(x.size());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Evaluation one = evaluate(*make({e}), x, p);
    reference.value += one.value;
    reference.gradient += one.gradient;
    reference.hessian.insert(reference.hessian.end(), one.hessian.begin(), one.hessian.end());
  }
  omp_set_num_threads(1);
  const Evaluation serial = evaluate(*term, x, p);
  EXPECT_NEAR(serial.value, reference.value, 1e-12 * std::abs(reference.value));
  EXPECT_LE((serial.gradient - reference.gradient).norm(), 1e-12 * reference.gradient.norm());
  ASSERT_EQ(serial.hessian.size(), reference.hessian.size());
  EXPECT_TRUE(serial.hessian == reference.hessian) << "element Hessians must land in their own slots";

  for (int threads : {2, 3}) {
    omp_set_num_threads(threads);
    expect_identical(evaluate(*term, x, p), serial, std::to_string(threads) + " OpenMP threads");
  }

  // Two threads evaluate the same term at the same time, each with its own output.
  omp_set_num_threads(2);
  Evaluation concurrent[2];
  for (int round = 0; round < 3; ++round) {
    std::thread first([&] { concurrent[0] = evaluate(*term, x, p); });
    std::thread second([&] { concurrent[1] = evaluate(*term, x, p); });
    first.join();
    second.join();
    expect_identical(concurrent[0], serial, "first of two concurrent evaluations");
    expect_identical(concurrent[1], serial, "second of two concurrent evaluations");
  }
  omp_set_num_threads(saved_threads);
}

TEST(ElementLoop, ElasticTermIsDeterministicAndReentrant) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 1, 1), 9, 3, 3);
  const Vector p = testing::heterogeneous_parameters(mesh, 1e3, 0.3);
  check_loop(mesh, perturbed_rest(mesh, 0.03), p, [&](std::vector<int> elements) -> std::unique_ptr<EnergyTerm> {
    return std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), 0,
                                            mesh.num_elements(), std::move(elements));
  });
}

TEST(ElementLoop, PlaneStrainElasticTermIsDeterministicAndReentrant) {
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(4, 1), 24, 8);
  const Vector p = testing::heterogeneous_parameters(mesh, 1e3, 0.3);
  check_loop(mesh, perturbed_rest(mesh, 0.02), p, [&](std::vector<int> elements) -> std::unique_ptr<EnergyTerm> {
    return std::make_unique<ElasticTerm<2>>(mesh, make_material<2>(MaterialKind::corotated), 0,
                                            mesh.num_elements(), std::move(elements));
  });
}

TEST(ElementLoop, SplineElasticTermIsDeterministicAndReentrant) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 1, 1), 9, 3, 3);
  const PrincipalStretchCurves curves =
      principal_stretch_preset(SplinePreset::neo_hookean, lame_from_young_poisson(1e3, 0.3));
  const Vector p = curves.controls();
  check_loop(mesh, perturbed_rest(mesh, 0.03), p, [&](std::vector<int> elements) -> std::unique_ptr<EnergyTerm> {
    return std::make_unique<SplineElasticTerm<3>>(mesh, curves, 0, std::move(elements));
  });
}

// Quadratic elements: 10 nodes per element through the same loop. check_loop takes the corner
// mesh for the element count; the state covers every node.
TEST(ElementLoop, QuadraticElasticTermIsDeterministicAndReentrant) {
  const QuadraticMesh q = make_quadratic_mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 1, 1), 9, 3, 2));
  const Vector p = testing::heterogeneous_parameters(q.corners, 1e3, 0.3);
  Vector x = quadratic_rest_state(q);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (int i = 0; i < x.size(); ++i) x[i] += u(rng);
  check_loop(q.corners, x, p, [&](std::vector<int> elements) -> std::unique_ptr<EnergyTerm> {
    return std::make_unique<QuadraticElasticTerm<3>>(q, make_material<3>(MaterialKind::stvk), 0, q.num_elements(),
                                                     std::move(elements));
  });
}

// A material that refuses its parameters inside the parallel loop is an exception at the caller
// -- that of the lowest chunk, for every thread count -- not a std::terminate from inside the
// OpenMP region (which would end this test binary, or a Python interpreter).
TEST(ElementLoop, AnExceptionInTheParallelLoopReachesTheCaller) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 1, 1), 9, 3, 3);
  ASSERT_GT(mesh.num_elements(), 300);  // two chunks of 256
  Vector p = testing::heterogeneous_parameters(mesh, 1e3, 0.3);
  p[300] = std::numeric_limits<double>::quiet_NaN();  // chunk 1
  p[40] = -1.0;                                       // chunk 0: its error is the one reported
  const ElasticTerm<3> term(mesh, make_material<3>(MaterialKind::neo_hookean), 0, mesh.num_elements());
  const Vector x = perturbed_rest(mesh, 0.03);
  const int saved_threads = omp_get_max_threads();
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    try {
      evaluate(term, x, p);
      ADD_FAILURE() << threads << " threads: E = -1 was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("got E = -1"), std::string::npos) << threads << ": " << e.what();
    }
    Vector gradient_p = Vector::Zero(p.size());
    EXPECT_THROW(term.add_mixed_transpose_times(x, p, Vector::Ones(x.size()), gradient_p), std::invalid_argument)
        << threads << " threads";
  }
  omp_set_num_threads(saved_threads);
}

}  // namespace
}  // namespace tailor::element_loop_test
