// The PETSc back-end (petsc/petsc_linear_solver.hpp) under MPI, against CHOLMOD: the same
// static inverse problem (a clamped bar bent by an end traction, per-element log E design) is
// solved by each; the reference is the CHOLMOD path (NewtonOptions::linear_solver empty). Run
// on 1 and 2 ranks (tests/petsc/CMakeLists.txt).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "../support/inverse_fixtures.hpp"
#include "../support/traction_bar.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/dynamics/time_integrator.hpp"
#include "forward/fem/loads.hpp"
#include "forward/solve/hessian_share.hpp"
#include "petsc/petsc_linear_solver.hpp"

namespace tailor::petsc_solver_test {
namespace {

using namespace tailor::testing;

// The adjoint tests' bar (tests/support/traction_bar.hpp) at 8 x 2 x 2 cells, with the linear
// solver given (null: CHOLMOD).
struct BarProblem : TractionBar {
  BarProblem(MaterialKind kind, double load) : TractionBar(kind, load, Eigen::Vector3i(8, 2, 2)) {}
  StaticFunctional functional(LinearSolverPtr solver) {
    StaticFunctionalOptions options;
    options.newton.linear_solver = std::move(solver);
    return TractionBar::functional(1e-6, options);
  }
};

double relative_difference(const Vector& a, const Vector& b) { return (a - b).norm() / b.norm(); }

// The largest difference of v between the ranks (every rank must hold the same full vector).
double spread_across_ranks(const Vector& v) {
  Vector low = v, high = v;
  MPI_Allreduce(MPI_IN_PLACE, low.data(), static_cast<int>(low.size()), MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, high.data(), static_cast<int>(high.size()), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return (high - low).lpNorm<Eigen::Infinity>();
}

void expect_matches_cholmod(MaterialKind kind, double load, const std::string& petsc_options,
                            bool by_parts = false) {
  BarProblem bar(kind, load);
  StaticFunctional reference = bar.functional(nullptr);
  Vector g_ref;
  const double j_ref = reference.value_and_gradient(bar.z0(), g_ref);

  PetscSolverOptions options;
  options.options = petsc_options;
  auto solver = std::make_shared<PetscLinearSolver>(options);
  EXPECT_EQ(solver->assembles_by_parts(), by_parts);
  StaticFunctional f = bar.functional(solver);
  Vector g;
  const double j = f.value_and_gradient(bar.z0(), g);
  if (PetscSession::rank() == 0)
    std::printf("%s, %s: state %.2e, gradient %.2e relative to CHOLMOD; adjoint %d iterations, residual %.1e\n",
              kind == MaterialKind::linear ? "linear" : "Neo-Hookean", solver->method().c_str(),
              relative_difference(f.state(), reference.state()), relative_difference(g, g_ref),
              f.last_linear_solve().iterations, f.last_linear_solve().relative_residual);
  EXPECT_EQ(f.last_hessian_solve(), HessianSolve::external_solver);
  EXPECT_LE(f.last_linear_solve().relative_residual, 1e-11);
  EXPECT_LT(relative_difference(f.state(), reference.state()), 1e-8);
  EXPECT_LT(relative_difference(g, g_ref), 1e-8);
  EXPECT_NEAR(j, j_ref, 1e-8 * std::abs(j_ref));
  EXPECT_EQ(spread_across_ranks(f.state()), 0.0);
  EXPECT_EQ(spread_across_ranks(g), 0.0);
}

TEST(PetscLinearSolver, LinearBarStateAndGradientMatchCholmodWithCgGamg) {
  expect_matches_cholmod(MaterialKind::linear, 20.0, "");
}

TEST(PetscLinearSolver, NeoHookeanBarStateAndGradientMatchCholmodWithCgGamg) {
  expect_matches_cholmod(MaterialKind::neo_hookean, 60.0, "-ksp_type cg -pc_type gamg");
}

TEST(PetscLinearSolver, NeoHookeanBarMatchesCholmodWithMumps) {
  expect_matches_cholmod(MaterialKind::neo_hookean, 60.0,
                         "-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps");
}

// Distributed assembly (-tailor_assemble_by_parts): every rank assembles the elements it owns,
// PETSc sums the shares; Newton's steps and the adjoint must give CHOLMOD's state and gradient.
TEST(PetscLinearSolver, AssemblyByPartsMatchesCholmod) {
  expect_matches_cholmod(MaterialKind::neo_hookean, 60.0, "-tailor_assemble_by_parts", true);
  expect_matches_cholmod(MaterialKind::linear, 20.0,
                         "-tailor_assemble_by_parts -ksp_type preonly -pc_type cholesky "
                         "-pc_factor_mat_solver_type mumps",
                         true);
}

// The shares (forward/solve/hessian_share.hpp) sum to the replicated Hessian: products with
// the summed matrix against the whole symmetric H at a deformed state, its norms against H's,
// every element slot in exactly one share, and each rank's share smaller than the whole on
// more than one rank. Both splits: by rows, and by whole vertices (with coordinates).
TEST(PetscLinearSolver, HessianSharesSumToTheHessian) {
  BarProblem bar(MaterialKind::neo_hookean, 60.0);
  ReducedAssembler assembler(*bar.model);
  SparseMatrix h;
  Vector y = bar.model->elimination().restrict_state(bar.rest);
  y += 0.01 * Vector::LinSpaced(y.size(), -1.0, 1.0).array().sin().matrix();
  assembler.evaluate(y, bar.p0, nullptr, nullptr, &h, HessianMode::exact);
  const SparseMatrix whole = h.selfadjointView<Eigen::Upper>();
  for (const bool by_vertices : {false, true}) {
    PetscSolverOptions options;
    options.assemble_by_parts = true;
    PetscLinearSolver solver(options);
    if (by_vertices) solver.set_vertex_coordinates(3, bar.model->elimination().restrict_state(bar.rest));
    HessianShare share(*bar.model, solver);
    share.assemble(y, bar.p0, HessianMode::exact);
    std::string message;
    ASSERT_TRUE(solver.setup_share(share.hessian(), message)) << message;
    for (int k = 0; k < 3; ++k) {
      const Vector v = Vector::LinSpaced(h.rows(), -1.0 + k, 2.0 * k + 1.0).array().cos().matrix();
      const Vector reference = whole * v;
      EXPECT_LT((solver.multiply(v) - reference).norm(), 1e-13 * reference.norm()) << by_vertices;
    }
    double norm = 0.0, max_diagonal = 0.0, min_diagonal = 0.0;
    ASSERT_TRUE(solver.matrix_norms(norm, max_diagonal, min_diagonal));
    Vector row_sums = Vector::Zero(h.rows());
    for (int j = 0; j < whole.outerSize(); ++j)
      for (SparseMatrix::InnerIterator e(whole, j); e; ++e) row_sums[e.row()] += std::abs(e.value());
    const Vector diagonal = whole.diagonal().cwiseAbs();
    EXPECT_NEAR(norm, row_sums.maxCoeff(), 1e-12 * norm);
    EXPECT_NEAR(max_diagonal, diagonal.maxCoeff(), 1e-12 * max_diagonal);
    EXPECT_NEAR(min_diagonal, diagonal.minCoeff(), 1e-12 * min_diagonal);
    long long slots = static_cast<long long>(share.num_slots()), total = 0;
    MPI_Allreduce(&slots, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(total, static_cast<long long>(assembler.num_slots()));
    if (PetscSession::size() > 1) {
      EXPECT_LT(slots, total);
    }
    if (PetscSession::rank() == 0)
      std::printf("Hessian shares (%s) on %d ranks: rank 0 has %lld of %lld slots\n",
                  by_vertices ? "by vertices" : "by rows", PetscSession::size(), slots, total);
  }
}

// A dynamic scene keeps its replicated assembly: a solver that assembles by parts is refused.
TEST(PetscLinearSolver, AssemblyByPartsIsRefusedByTheTimeIntegrator) {
  BarProblem bar(MaterialKind::linear, 20.0);
  PetscSolverOptions options;
  options.assemble_by_parts = true;
  TimeIntegratorOptions integrator;
  integrator.time_step = 0.01;
  integrator.newton.linear_solver = std::make_shared<PetscLinearSolver>(options);
  try {
    TimeIntegrator refused(*bar.model, integrator);
    ADD_FAILURE() << "a solver that assembles by parts was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("assembles by parts"), std::string::npos) << e.what();
  }
}

TEST(PetscLinearSolver, TaylorTestUnderMpi) {
  BarProblem bar(MaterialKind::neo_hookean, 60.0);
  StaticFunctional f = bar.functional(std::make_shared<PetscLinearSolver>());
  const TaylorTestResult t = taylor_test(f, bar.z0());
  if (PetscSession::rank() == 0) std::printf("Neo-Hookean bar on %d ranks:\n%s", PetscSession::size(), t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9) << t.table();
  EXPECT_NEAR(t.rate0, 1.0, 0.2) << t.table();
}

// The tolerance given to solve() is met (the adjoint's rule), and the default one otherwise.
TEST(PetscLinearSolver, SolveMeetsTheRequestedTolerance) {
  BarProblem bar(MaterialKind::linear, 20.0);
  ReducedAssembler assembler(*bar.model);
  SparseMatrix h;
  const Vector y = bar.model->elimination().restrict_state(bar.rest);
  assembler.evaluate(y, bar.p0, nullptr, nullptr, &h, HessianMode::exact);
  PetscLinearSolver solver;
  std::string message;
  ASSERT_TRUE(solver.setup(h, message)) << message;
  const Vector b = Vector::Ones(h.rows());
  Vector x;
  for (double tol : {1e-4, 1e-12}) {
    const LinearSolveStats stats = solver.solve(b, tol, x);
    EXPECT_TRUE(stats.converged) << stats.message;
    EXPECT_EQ(stats.relative_tolerance, tol);
    EXPECT_LE(stats.relative_residual, 10 * tol);
  }
  const LinearSolveStats stats = solver.solve(b, 0.0, x);
  EXPECT_EQ(stats.relative_tolerance, 1e-10);
  EXPECT_LE(stats.relative_residual, 1e-9);
}

// The rigid-body near-null space (set_vertex_coordinates): the rows split by whole vertices,
// the same solution as without it, and GAMG needs fewer CG iterations with it (the point of
// giving it: smoothed aggregation builds its coarse spaces from these modes).
TEST(PetscLinearSolver, RigidBodyModesHelpGamg) {
  TractionBar bar(MaterialKind::linear, 20.0, Eigen::Vector3i(24, 6, 6));  // GAMG gets coarse levels
  ReducedAssembler assembler(*bar.model);
  SparseMatrix h;
  const Vector y = bar.model->elimination().restrict_state(bar.rest);
  assembler.evaluate(y, bar.p0, nullptr, nullptr, &h, HessianMode::exact);
  const Vector b = Vector::LinSpaced(h.rows(), -1.0, 1.0);
  Vector plain_x, modes_x;
  PetscLinearSolver plain, modes;
  // The bar is clamped in every component at x = 0: the free unknowns are whole vertices, and
  // restrict_state(rest) are their coordinates.
  modes.set_vertex_coordinates(3, y);
  std::string message;
  ASSERT_TRUE(plain.setup(h, message)) << message;
  ASSERT_TRUE(modes.setup(h, message)) << message;
  const LinearSolveStats p = plain.solve(b, 1e-12, plain_x), m = modes.solve(b, 1e-12, modes_x);
  ASSERT_TRUE(p.converged && m.converged) << p.message << m.message;
  EXPECT_FALSE(plain.info().near_null_space);
  EXPECT_TRUE(modes.info().near_null_space);
  EXPECT_EQ(modes.info().processes, PetscSession::size());
  EXPECT_EQ(modes.info().solves, 1);
  EXPECT_EQ(modes.info().last.iterations, m.iterations);
  if (PetscSession::rank() == 0)
    std::printf("GAMG on %d ranks, %d unknowns: %d CG iterations without the rigid-body modes, %d with\n",
                PetscSession::size(), static_cast<int>(h.rows()), p.iterations, m.iterations);
  EXPECT_LE(m.relative_residual, 1e-11);
  EXPECT_LT(relative_difference(modes_x, plain_x), 1e-9);
  EXPECT_LT(m.iterations, p.iterations);
  EXPECT_EQ(spread_across_ranks(modes_x), 0.0);
  EXPECT_THROW(modes.set_vertex_coordinates(3, Vector::Zero(4)), std::invalid_argument);
}

TEST(PetscLinearSolver, BadOptionsAreClearErrors) {
  PetscSolverOptions bad_type;
  bad_type.options = "-ksp_type no_such_method";
  try {
    PetscLinearSolver solver(bad_type);
    ADD_FAILURE() << "an unknown KSP type was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_method"), std::string::npos) << e.what();
  }
  // A misspelt option is never read: the first solve says so.
  BarProblem bar(MaterialKind::linear, 20.0);
  PetscSolverOptions misspelt;
  misspelt.options = "-ksp_rtoll 1e-8";
  StaticFunctional f = bar.functional(std::make_shared<PetscLinearSolver>(misspelt));
  try {
    f.value(bar.z0());
    ADD_FAILURE() << "a misspelt option was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("-ksp_rtoll"), std::string::npos) << e.what();
  }
  // The options of the failed solvers are gone: a default solver works.
  PetscLinearSolver fine;
  EXPECT_EQ(fine.method(), "cg/gamg");
}

}  // namespace
}  // namespace tailor::petsc_solver_test
