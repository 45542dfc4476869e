// The vertex-block rule of the descent solver, shared by the host and the CUDA device
// (forward/dynamics/descent_tet_kernels.hpp, descent_vertex_blocks.hpp; docs/dynamics.md,
// "The GPU path"):
//  - the host instantiation of the per-tet math against ElasticTerm's element loop (energy,
//    gradient and the exact element Hessian's diagonal blocks) on a randomly deformed bar with
//    inverted tets, for stable Neo-Hookean and StVK; the gradient and blocks against central
//    differences (and a perturbed gradient fails the same check);
//  - the 3x3 PSD projection against symmetric_eigen's eigen-decomposition;
//  - the host pass (incidence gather, constant terms as their quadratic) against the model's
//    assembled energy, gradient and exact Hessian diagonal blocks (Neo-Hookean's blocks are PSD);
//  - the solver on the CPU with this rule: accepted iterates never raise the potential, it reaches
//    Newton's minimizer, and its iterates do not depend on the thread count;
//  - device selection: "gpu" without a device is an error, "auto" falls back to the CPU, a model
//    the rule does not cover is refused;
//  - with CUDA and a device: device passes and iterates against the CPU's to round-off.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "../../support/dynamics_fixtures.hpp"
#include "forward/core/assembler.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/dynamics/descent_device.hpp"
#include "forward/dynamics/descent_time_stepper.hpp"
#include "forward/dynamics/descent_vertex_blocks.hpp"
#include "forward/fem/elastic_term.hpp"
#include "tailor_cuda_config.hpp"
#ifdef TAILOR_HAVE_CUDA
#include "forward/dynamics/descent_cuda.hpp"
#endif

namespace tailor::descent_kernels_test {
namespace {

using namespace tailor::testing;
namespace dk = descent_kernels;

const ElasticTerm<3>& elastic_of(const Model& model) {
  for (const auto& t : model.terms())
    if (const auto* e = dynamic_cast<const ElasticTerm<3>*>(t.get())) return *e;
  throw std::logic_error("no elastic term");
}

Vector randomly_deformed(const Vector& rest, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector x = rest;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += amplitude * u(rng);
  return x;
}

// The 12 positions of covered element k.
void element_positions(const ElasticTerm<3>& term, const Vector& x, int k, double* out) {
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 3; ++j) out[3 * a + j] = x[3 * term.element_vertices(k)[a] + j];
}

void shape(const ElasticTerm<3>& term, int k, double* G) {
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 3; ++j) G[3 * a + j] = term.shape_gradients(k)(a, j);
}

void compare_with_element_loop(MaterialKind kind, int material) {
  Cantilever c(descent_bar_options(12, kind));
  const ElasticTerm<3>& term = elastic_of(*c.model);
  const Vector x = randomly_deformed(c.rest, 0.15, 7);
  const int m = static_cast<int>(term.elements().size());
  HessianPattern pattern;
  term.hessian_pattern(pattern);
  std::vector<double> slots(pattern.size());
  double energy = 0.0;
  Vector gradient = Vector::Zero(x.size());
  EnergyRequest request;
  request.value = &energy;
  request.gradient = &gradient;
  request.hessian_values = slots.data();
  request.hessian_mode = HessianMode::exact;
  term.evaluate(x, c.p, request);
  double kernel_energy = 0.0, block_error = 0.0, block_size = 0.0;
  Vector kernel_gradient = Vector::Zero(x.size());
  int inverted = 0;
  for (int k = 0; k < m; ++k) {
    double xe[12], G[12], g[12], B[36], F[9], C[9];
    element_positions(term, x, k, xe);
    shape(term, k, G);
    dk::deformation_gradient(xe, G, F);
    if (dk::cofactor(F, C) < 0.0) ++inverted;
    const LameParameters lame = term.element_lame(c.p, k);
    kernel_energy += dk::tet_element(material, xe, G, term.rest_volume(k), lame.lambda, lame.mu, g, B, false);
    for (int a = 0; a < 4; ++a)
      for (int j = 0; j < 3; ++j) kernel_gradient[3 * term.element_vertices(k)[a] + j] += g[3 * a + j];
    // The element's slots are its 12 x 12 Hessian, row-major; block (a, a) at rows/cols 3a..3a+2.
    const double* H = slots.data() + 144 * static_cast<std::size_t>(k);
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          block_error = std::max(block_error, std::abs(B[9 * a + 3 * i + j] - H[12 * (3 * a + i) + 3 * a + j]));
          block_size = std::max(block_size, std::abs(H[12 * (3 * a + i) + 3 * a + j]));
        }
  }
  EXPECT_GT(inverted, 0) << "the deformation should invert some tets";
  EXPECT_NEAR(kernel_energy, energy, 1e-12 * std::abs(energy));
  EXPECT_LE((kernel_gradient - gradient).lpNorm<Eigen::Infinity>(), 1e-12 * gradient.lpNorm<Eigen::Infinity>());
  EXPECT_LE(block_error, 1e-12 * block_size);
}

TEST(DescentKernels, NeoHookeanTetMatchesTheElementLoop) { compare_with_element_loop(MaterialKind::neo_hookean, dk::kNeoHookean); }
TEST(DescentKernels, StvkTetMatchesTheElementLoop) { compare_with_element_loop(MaterialKind::stvk, dk::kStvk); }

// Central differences of the energy (gradient) and of the gradient (diagonal blocks) at an
// inverted tet; `tamper` scales one gradient entry to show that the check sees such an error.
double finite_difference_error(int material, double tamper) {
  const double G[12] = {-1.1, -0.9, -1.0, 1.0, 0.1, 0.0, 0.1, 0.8, 0.05, 0.0, 0.0, 0.95};
  const double x0[12] = {0.0, 0.0, 0.0, 0.9, 0.2, -0.1, 0.1, 1.1, 0.3, 0.2, 0.1, -0.7};  // J < 0
  const double V = 0.2, lambda = 3.0, mu = 1.5, h = 1e-6;
  double g[12], B[36];
  dk::tet_element(material, x0, G, V, lambda, mu, g, B, false);
  g[4] *= tamper;
  double error = 0.0, scale = 0.0;
  for (int r = 0; r < 12; ++r) {
    double xp[12], xm[12], gp[12], gm[12];
    for (int k = 0; k < 12; ++k) xp[k] = xm[k] = x0[k];
    xp[r] += h, xm[r] -= h;
    const double ep = dk::tet_element(material, xp, G, V, lambda, mu, gp, nullptr, false);
    const double em = dk::tet_element(material, xm, G, V, lambda, mu, gm, nullptr, false);
    error = std::max(error, std::abs((ep - em) / (2 * h) - g[r]));
    scale = std::max(scale, std::abs(g[r]));
    const int a = r / 3, i = r % 3;  // column i of block (a, a)
    for (int j = 0; j < 3; ++j) {
      error = std::max(error, std::abs((gp[3 * a + j] - gm[3 * a + j]) / (2 * h) - B[9 * a + 3 * j + i]));
      scale = std::max(scale, std::abs(B[9 * a + 3 * j + i]));
    }
  }
  return error / scale;
}

TEST(DescentKernels, GradientAndBlocksPassFiniteDifferences) {
  for (const int material : {dk::kNeoHookean, dk::kStvk}) {
    EXPECT_LT(finite_difference_error(material, 1.0), 1e-7) << "material " << material;
    EXPECT_GT(finite_difference_error(material, 1.001), 1e-5) << "the check should see a 0.1% error";
  }
}

TEST(DescentKernels, ProjectionClampsNegativeEigenvalues) {
  // Reference: symmetric_eigen (Eigen's solver), eigenvalues clamped at 0.
  const double cases[3][9] = {{2.0, 0.5, -0.3, 0.5, -1.0, 0.7, -0.3, 0.7, 0.4},
                              {4.0, 1.0, 0.0, 1.0, 3.0, 0.5, 0.0, 0.5, 2.0},  // SPD: unchanged
                              {-1.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 5.0}};
  for (const auto& c : cases) {
    double A[9];
    for (int k = 0; k < 9; ++k) A[k] = c[k];
    dk::project_psd(A);
    const Eigen::Matrix3d M = Eigen::Map<const Eigen::Matrix3d>(c);
    Eigen::Vector3d values;
    Eigen::Matrix3d vectors;
    symmetric_eigen<3>(M, values, vectors);
    const Eigen::Matrix3d expected = vectors * values.cwiseMax(0.0).asDiagonal() * vectors.transpose();
    EXPECT_LT((Eigen::Map<const Eigen::Matrix3d>(A) - expected).norm(), 1e-13 * M.norm());
  }
}

TEST(DescentKernels, HostPassMatchesTheAssembledModel) {
  Cantilever c(descent_bar_options(12));
  TimeIntegrator integrator(*c.model, TimeIntegratorOptions{});
  DynamicState s = integrator.initial_state(c.rest, Vector::Zero(c.rest.size()), c.p);
  integrator.configure_step(s, c.p);
  VertexBlockModel rule(*c.model);
  // Every corner at a free vertex is listed once, at its vertex's block.
  const auto& begin = rule.incidence_begin();
  int corners_at_free = 0;
  for (std::size_t b = 0; b + 1 < begin.size(); ++b)
    for (int t = begin[b]; t < begin[b + 1]; ++t) {
      ASSERT_EQ(rule.tet_vertex()[rule.incidence()[t]], rule.block_vertex()[b]);
      ++corners_at_free;
    }
  int expected_corners = 0;
  for (const int v : rule.tet_vertex()) expected_corners += c.mesh.rest_positions(v, 0) > 1e-9 ? 1 : 0;
  EXPECT_EQ(corners_at_free, expected_corners);
  // The pass at a deformed state y, the constant part expanded about another state y0.
  const Vector y0 = c.model->elimination().restrict_state(c.rest);
  const Vector y = c.model->elimination().restrict_state(randomly_deformed(c.rest, 0.02, 3));
  rule.prepare(c.p, y0);
  VertexBlockHostPass pass(rule);
  VertexBlockHostPass::Result at;
  pass.evaluate(y, at, true);
  ReducedAssembler assembler(*c.model);
  SparseMatrix H = assembler.hessian_pattern_matrix();
  double energy = 0;
  Vector g;
  assembler.evaluate(y, c.p, &energy, &g, &H, HessianMode::exact);
  EXPECT_NEAR(at.energy, energy, 1e-12 * std::abs(energy));
  EXPECT_LT((at.gradient - g).norm(), 1e-11 * g.norm());
  // Neo-Hookean's diagonal blocks are PSD, so the rule's blocks are the exact Hessian's.
  const Matrix dense = Matrix(H).selfadjointView<Eigen::Upper>();
  const Vector w = Vector::LinSpaced(y.size(), -1.0, 2.0);
  Vector expected(y.size()), direction;
  for (int b = 0; b < y.size() / 3; ++b)
    expected.segment<3>(3 * b) = dense.block<3, 3>(3 * b, 3 * b).ldlt().solve(w.segment<3>(3 * b));
  pass.apply_inverse(at, w, direction);
  EXPECT_LT((direction - expected).norm(), 1e-10 * expected.norm());
}

Vector swing_velocity(const Cantilever& c, double tip_speed) {
  Vector v = Vector::Zero(c.rest.size());
  const double length = c.rest.maxCoeff();
  for (int i = 0; i < c.mesh.num_vertices(); ++i) v[3 * i + 2] = tip_speed * c.rest[3 * i] / length;
  return v;
}

DescentOptions vertex_block_options() {
  DescentOptions o;
  o.preconditioner = DescentPreconditioner::vertex_blocks;
  return o;
}

TEST(DescentKernels, SolverWithTheRuleNeverRaisesTheEnergyAndReachesNewton) {
  Cantilever c(descent_bar_options(48));
  TimeIntegratorOptions io;
  io.time_step = 0.05;
  TimeIntegrator integrator(*c.model, io);
  Vector squeezed = c.rest;
  for (int i = 0; i < c.mesh.num_vertices(); ++i) squeezed[3 * i] *= 0.5;
  DynamicState s = integrator.initial_state(squeezed, swing_velocity(c, 10.0), c.p);
  DescentOptions o = vertex_block_options();
  o.max_iterations = 300, o.keep_history = true, o.step_length = 1.0, o.rho = 0.995;
  DescentTimeStepper stepper(integrator, o);
  EXPECT_EQ(stepper.solver().device(), "cpu");
  const DescentResult r = stepper.step(s, c.p);
  double energy = r.initial_energy, rise = 0.0;
  for (const DescentIteration& it : r.history)
    if (it.accepted) rise = std::max(rise, it.energy - energy), energy = it.energy;
  EXPECT_LE(rise, 1e-12 * std::abs(r.initial_energy));
  EXPECT_GT(r.rejections, 0) << "the rule never acted";
  // Converged descent against Newton's step (relative tolerance 1e-10) from a gentler start.
  Cantilever d(descent_bar_options(12));
  TimeIntegratorOptions jo;
  jo.time_step = 0.02;
  TimeIntegrator newton(*d.model, jo);
  DynamicState reference = newton.initial_state(d.rest, swing_velocity(d, 5.0), d.p);
  DynamicState descended = reference;
  DescentOptions tight = vertex_block_options();
  tight.relative_tolerance = 1e-7, tight.max_iterations = 20000;
  DescentTimeStepper descent(newton, tight);
  ASSERT_TRUE(descent.step(descended, d.p).converged());
  ASSERT_TRUE(newton.step(reference, d.p).converged());
  const double moved = (reference.x - d.rest).lpNorm<Eigen::Infinity>();
  EXPECT_LT((descended.x - reference.x).lpNorm<Eigen::Infinity>(), 1e-5 * moved);
}

TEST(DescentKernels, RuleIteratesAreTheSameForOneAndTwoThreads) {
  Cantilever c(descent_bar_options(48));
  const int saved = omp_get_max_threads();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    TimeIntegratorOptions io;
    io.time_step = 0.02;
    TimeIntegrator integrator(*c.model, io);
    DynamicState s = integrator.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
    DescentOptions o = vertex_block_options();
    o.max_iterations = 40;
    DescentTimeStepper stepper(integrator, o);
    for (int n = 0; n < 2; ++n) stepper.step(s, c.p);
    return s.x;
  };
  const Vector one = run(1), two = run(2);
  omp_set_num_threads(saved);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DescentKernels, DeviceSelection) {
  Cantilever c(descent_bar_options(12));
  DescentOptions o;
  o.device = DescentDevice::automatic;
  if (!cuda_device_usable()) {
    EXPECT_EQ(DescentSolver(*c.model, o).device(), "cpu");
    o.device = DescentDevice::gpu;
    try {
      DescentSolver solver(*c.model, o);
      ADD_FAILURE() << "\"gpu\" without a device should throw";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("gpu"), std::string::npos) << e.what();
    }
  }
  // The rule does not cover the corotated material: refused on the CPU, and "auto" keeps the
  // projected-Hessian CPU path.
  Cantilever corotated(descent_bar_options(12, MaterialKind::corotated));
  EXPECT_FALSE(VertexBlockModel::check(*corotated.model).empty());
  EXPECT_THROW(DescentSolver(*corotated.model, vertex_block_options()), std::invalid_argument);
  o.device = DescentDevice::automatic;
  EXPECT_EQ(DescentSolver(*corotated.model, o).device(), "cpu");
  EXPECT_NO_THROW(DescentSolver(*corotated.model, o).pass());
}

#ifdef TAILOR_HAVE_CUDA
TEST(DescentKernels, DevicePassMatchesTheHost) {
  if (!cuda_device_usable()) GTEST_SKIP() << "no CUDA device";
  Cantilever c(descent_bar_options(24));
  TimeIntegrator integrator(*c.model, TimeIntegratorOptions{});
  DynamicState s = integrator.initial_state(c.rest, Vector::Zero(c.rest.size()), c.p);
  integrator.configure_step(s, c.p);
  const Vector y = c.model->elimination().restrict_state(randomly_deformed(c.rest, 0.02, 5));
  VertexBlockModel rule(*c.model);
  rule.prepare(c.p, y);
  VertexBlockHostPass host(rule);
  VertexBlockHostPass::Result at;
  host.evaluate(y, at, true);
  cuda::VertexBlockDevice device(rule.layout(), c.model->num_dofs());
  const auto sums = device.start(rule.layout(), rule.start_positions().data());
  Vector gradient(y.size());
  std::vector<double> inverse(at.block_inverse.size());
  device.read_evaluation(gradient.data(), inverse.data());
  EXPECT_NEAR(sums.elastic_energy + rule.e0() + sums.quadratic_energy, at.energy, 1e-12 * std::abs(at.energy));
  EXPECT_LE((gradient - at.gradient).lpNorm<Eigen::Infinity>(), 1e-12 * at.gradient.lpNorm<Eigen::Infinity>());
  double worst = 0.0, largest = 0.0;
  for (std::size_t k = 0; k < inverse.size(); ++k)
    worst = std::max(worst, std::abs(inverse[k] - at.block_inverse[k])), largest = std::max(largest, std::abs(at.block_inverse[k]));
  EXPECT_LE(worst, 1e-12 * largest);
}

TEST(DescentKernels, DeviceIteratesMatchTheCpuAndNeverRaiseTheEnergy) {
  if (!cuda_device_usable()) GTEST_SKIP() << "no CUDA device";
  Cantilever c(descent_bar_options(24));
  TimeIntegratorOptions io;
  io.time_step = 0.02;
  auto run = [&](DescentDevice device) {
    TimeIntegrator integrator(*c.model, io);
    DynamicState s = integrator.initial_state(c.rest, swing_velocity(c, 5.0), c.p);
    DescentOptions o = vertex_block_options();
    o.device = device, o.max_iterations = 30, o.keep_history = true;
    DescentTimeStepper stepper(integrator, o);
    EXPECT_EQ(stepper.solver().device(), device == DescentDevice::gpu ? "gpu" : "cpu");
    double rise = 0.0;
    for (int n = 0; n < 3; ++n) {
      const DescentResult r = stepper.step(s, c.p);
      double energy = r.initial_energy;
      for (const DescentIteration& it : r.history)
        if (it.accepted) rise = std::max(rise, (it.energy - energy) / std::abs(r.initial_energy)), energy = it.energy;
    }
    return std::make_pair(s.x, rise);
  };
  const auto [cpu, cpu_rise] = run(DescentDevice::cpu);
  const auto [gpu, gpu_rise] = run(DescentDevice::gpu);
  (void)cpu_rise;
  EXPECT_LE(gpu_rise, 1e-12);
  EXPECT_LE((gpu - cpu).lpNorm<Eigen::Infinity>(), 1e-9 * (cpu - c.rest).lpNorm<Eigen::Infinity>());
}
#endif

}  // namespace
}  // namespace tailor::descent_kernels_test
