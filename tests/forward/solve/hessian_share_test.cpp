// Assembly by parts without MPI (forward/solve/hessian_share.hpp): stand-in solvers play the
// processes of a split of the rows. The reference is the whole reduced Hessian that
// ReducedAssembler assembles, and the CHOLMOD path of Newton and of the static adjoint.
#include "forward/solve/hessian_share.hpp"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <string>

#include "../../support/traction_bar.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::hessian_share_test {
namespace {

using namespace tailor::testing;

// Process `rank` of `size` with PETSc's default split of the rows (the first n % size processes
// get one more). As the only process (size 1) it also solves: it holds the sum of the shares it
// was given, which is then the whole Hessian.
class SplitSolver final : public LinearSolver {
 public:
  SplitSolver(int rank, int size) : rank_(rank), size_(size) {}
  std::string name() const override { return "split stand-in"; }
  bool assembles_by_parts() const override { return true; }
  bool owns_unknown(int unknown, int n) const override {
    const int base = n / size_, extra = n % size_;
    const int begin = rank_ * base + std::min(rank_, extra);
    return unknown >= begin && unknown < begin + base + (rank_ < extra ? 1 : 0);
  }
  bool setup(const SparseMatrix&, std::string& message) override {
    message = "assembly by parts: setup() of the whole matrix must not be called";
    return false;
  }
  bool setup_share(const SparseMatrix& upper, std::string& message) override {
    ++setups;
    held = upper.selfadjointView<Eigen::Upper>();
    ldlt.compute(held);
    if (ldlt.info() != Eigen::Success) message = "not positive definite";
    return ldlt.info() == Eigen::Success;
  }
  LinearSolveStats solve(const Vector& b, double, Vector& x) override {
    x = ldlt.solve(b);
    LinearSolveStats stats;
    stats.converged = x.allFinite();
    stats.relative_residual = (b - held * x).norm() / b.norm();
    return stats;
  }
  bool matrix_norms(double& inf_norm, double& max_diagonal, double& min_diagonal) const override {
    Vector row_sums = Vector::Zero(held.rows());
    for (int j = 0; j < held.outerSize(); ++j)
      for (SparseMatrix::InnerIterator e(held, j); e; ++e) row_sums[e.row()] += std::abs(e.value());
    inf_norm = row_sums.maxCoeff();
    max_diagonal = held.diagonal().cwiseAbs().maxCoeff();
    min_diagonal = held.diagonal().cwiseAbs().minCoeff();
    return true;
  }
  int setups = 0;
  SparseMatrix held;

 private:
  int rank_, size_;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt;
};

// Three processes' shares sum to the whole Hessian at a deformed Neo-Hookean state; every
// element slot is in exactly one share, each share is a real part (neither empty nor all);
// two processes get half of the elements each, within 5 percentage points.
TEST(HessianShare, SharesSumToTheWholeHessian) {
  TractionBar bar(MaterialKind::neo_hookean, 60.0, Eigen::Vector3i(8, 2, 2));
  ReducedAssembler whole(*bar.model);
  SparseMatrix h = whole.hessian_pattern_matrix();
  Vector y = bar.model->elimination().restrict_state(bar.rest);
  y += 0.01 * Vector::LinSpaced(y.size(), -1.0, 1.0).array().sin().matrix();
  whole.evaluate(y, bar.p0, nullptr, nullptr, &h, HessianMode::exact);
  SparseMatrix sum(h.rows(), h.cols());
  std::size_t slots = 0;
  for (int rank = 0; rank < 3; ++rank) {
    const SplitSolver process(rank, 3);
    HessianShare share(*bar.model, process);
    share.assemble(y, bar.p0, HessianMode::exact);
    sum += share.hessian();
    slots += share.num_slots();
    EXPECT_GT(share.num_slots(), 0u);
    EXPECT_LT(share.num_slots(), whole.num_slots());
  }
  EXPECT_EQ(slots, whole.num_slots());
  EXPECT_LT(SparseMatrix(sum - h).norm(), 1e-13 * h.norm());
  // The check sees a missing share: the first two alone are not H.
  SparseMatrix two(h.rows(), h.cols());
  for (int rank = 0; rank < 2; ++rank) {
    const SplitSolver process(rank, 3);
    HessianShare share(*bar.model, process);
    share.assemble(y, bar.p0, HessianMode::exact);
    two += share.hessian();
  }
  EXPECT_GT(SparseMatrix(two - h).norm(), 1e-3 * h.norm());
  // Two processes share the elements across their rows evenly (the hash in HessianShare; the
  // smallest unknown's owner alone gave the first process 86% of this bar's slots).
  const SplitSolver first(0, 2);
  const HessianShare half(*bar.model, first);
  EXPECT_NEAR(static_cast<double>(half.num_slots()), whole.num_slots() / 2.0, 0.05 * whole.num_slots());
}

// Newton and the static adjoint through assembly by parts (one process holding the one share):
// the same state and gradient as the CHOLMOD path, setup() of the whole matrix never called,
// and the Hessian never assembled whole (factorize_hessian refuses).
TEST(HessianShare, NewtonAndAdjointByPartsMatchCholmod) {
  TractionBar bar(MaterialKind::neo_hookean, 60.0, Eigen::Vector3i(8, 2, 2));
  StaticFunctional reference = bar.functional(1e-6);
  Vector g_ref;
  const double j_ref = reference.value_and_gradient(bar.z0(), g_ref);
  auto solver = std::make_shared<SplitSolver>(0, 1);
  StaticFunctionalOptions options;
  options.newton.linear_solver = solver;
  StaticFunctional f = bar.functional(1e-6, options);
  Vector g;
  const double j = f.value_and_gradient(bar.z0(), g);
  EXPECT_NEAR(j, j_ref, 1e-10 * std::abs(j_ref));
  EXPECT_LT((f.state() - reference.state()).norm(), 1e-10 * reference.state().norm());
  EXPECT_LT((g - g_ref).norm(), 1e-8 * g_ref.norm());
  EXPECT_GT(solver->setups, 1);
  EXPECT_EQ(f.last_hessian_solve(), HessianSolve::external_solver);

  NewtonSolver newton(*bar.model, options.newton);
  EXPECT_TRUE(newton.assembles_by_parts());
  EXPECT_EQ(newton.hessian().nonZeros(), 0);
  const Vector y = bar.model->elimination().restrict_state(bar.rest);
  EXPECT_THROW(newton.factorize_hessian(bar.p0, y, HessianMode::exact), std::logic_error);
}

}  // namespace
}  // namespace tailor::hessian_share_test
