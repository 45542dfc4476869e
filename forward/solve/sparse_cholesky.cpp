#include "forward/solve/sparse_cholesky.hpp"

#include <cholmod.h>

#include <limits>
#include <stdexcept>

#include "forward/solve/threads.hpp"

namespace tailor {
namespace {

// A view of an Eigen upper-triangular CSC matrix as a cholmod_sparse (no copy).
cholmod_sparse view(const SparseMatrix& upper) {
  cholmod_sparse a{};
  a.nrow = static_cast<std::size_t>(upper.rows());
  a.ncol = static_cast<std::size_t>(upper.cols());
  a.nzmax = static_cast<std::size_t>(upper.nonZeros());
  a.p = const_cast<int*>(upper.outerIndexPtr());
  a.i = const_cast<int*>(upper.innerIndexPtr());
  a.x = const_cast<double*>(upper.valuePtr());
  a.stype = 1;  // upper triangle stored, symmetric
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

cholmod_dense view(const double* data, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense d{};
  d.nrow = static_cast<std::size_t>(rows);
  d.ncol = static_cast<std::size_t>(cols);
  d.nzmax = d.nrow * d.ncol;
  d.d = d.nrow;
  d.x = const_cast<double*>(data);
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

}  // namespace

// One CHOLMOD workspace and factor, configured for either supernodal LL^T or simplicial LDL^T.
// (Outside the anonymous namespace: SparseCholesky::Impl, which has external linkage, holds it.)
struct CholmodFactor {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  explicit CholmodFactor(bool ldlt) {
    cholmod_start(&common);
    common.print = 0;  // statuses are reported through FactorizationResult
    if (ldlt) {
      common.supernodal = CHOLMOD_SIMPLICIAL;
      common.final_ll = 0;
    } else {
      common.supernodal = CHOLMOD_SUPERNODAL;
    }
  }
  ~CholmodFactor() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  void analyze(cholmod_sparse* a) {
    const FactorizationThreadsGuard threads;
    if (factor) cholmod_free_factor(&factor, &common);
    factor = cholmod_analyze(a, &common);
    if (!factor || common.status < CHOLMOD_OK)
      throw std::runtime_error("CHOLMOD symbolic analysis failed (status " + std::to_string(common.status) + ")");
    flops = common.fl;
    nonzeros = common.lnz;
  }
  double flops = 0.0, nonzeros = 0.0;  // of the analysed factor (cholmod_analyze's estimates)
};

struct SparseCholesky::Impl {
  CholmodFactor llt{false};
  std::unique_ptr<CholmodFactor> ldlt;  // created on first need
  std::size_t analyzed_nnz = 0;
  std::size_t ldlt_analyzed_nnz = 0;
  CholmodFactor* active = nullptr;
};

std::pair<double, double> estimate_factor_cost(const SparseMatrix& upper, FillOrdering ordering) {
  if (upper.rows() != upper.cols() || !upper.isCompressed())
    throw std::invalid_argument("estimate_factor_cost: expected a square compressed matrix");
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.nmethods = 1;
  common.method[0].ordering = ordering == FillOrdering::amd     ? CHOLMOD_AMD
                              : ordering == FillOrdering::metis ? CHOLMOD_METIS
                                                                : CHOLMOD_NESDIS;
  common.supernodal = CHOLMOD_SUPERNODAL;
  cholmod_sparse a = view(upper);
  cholmod_factor* factor = cholmod_analyze(&a, &common);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::pair<double, double> cost =
      factor && common.status == CHOLMOD_OK ? std::make_pair(common.lnz, common.fl) : std::make_pair(nan, nan);
  if (factor) cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  return cost;
}

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::analyze(const SparseMatrix& upper) {
  if (upper.rows() != upper.cols() || !upper.isCompressed())
    throw std::invalid_argument("SparseCholesky::analyze: expected a square compressed matrix");
  cholmod_sparse a = view(upper);
  impl_->llt.analyze(&a);
  impl_->analyzed_nnz = static_cast<std::size_t>(upper.nonZeros());
  impl_->ldlt_analyzed_nnz = 0;
  impl_->active = nullptr;
  rows_ = static_cast<int>(upper.rows());
}

FactorizationResult SparseCholesky::factorize(const SparseMatrix& upper) {
  low_rank_factors_.resize(rows_, 0);
  if (upper.rows() != rows_ || static_cast<std::size_t>(upper.nonZeros()) != impl_->analyzed_nnz ||
      !impl_->llt.factor)
    analyze(upper);
  FactorizationResult result;
  cholmod_sparse a = view(upper);
  impl_->active = nullptr;
  const FactorizationThreadsGuard threads;

  CholmodFactor& llt = impl_->llt;
  ++numeric_factorizations_;
  cholmod_factorize(&a, llt.factor, &llt.common);
  if (llt.common.status == CHOLMOD_OK && llt.factor->minor == llt.factor->n) {
    result.success = result.positive_definite = true;
    impl_->active = &llt;
    return result;
  }
  if (llt.common.status != CHOLMOD_NOT_POSDEF) {
    result.message = "CHOLMOD factorization failed (status " + std::to_string(llt.common.status) + ")";
    return result;
  }

  // Not positive definite: LDL^T of the same matrix.
  if (!impl_->ldlt) impl_->ldlt = std::make_unique<CholmodFactor>(true);
  CholmodFactor& ldlt = *impl_->ldlt;
  if (impl_->ldlt_analyzed_nnz != static_cast<std::size_t>(upper.nonZeros())) {
    ldlt.analyze(&a);
    impl_->ldlt_analyzed_nnz = static_cast<std::size_t>(upper.nonZeros());
  }
  ++numeric_factorizations_;
  cholmod_factorize(&a, ldlt.factor, &ldlt.common);
  if (ldlt.common.status != CHOLMOD_OK || ldlt.factor->minor != ldlt.factor->n) {
    result.message = "matrix is singular (zero pivot in LDL^T at column " + std::to_string(ldlt.factor->minor) + ")";
    return result;
  }
  // Simplicial LDL^T stores D on the diagonal of L (column start entries).
  const auto* p = static_cast<const int*>(ldlt.factor->p);
  const auto* x = static_cast<const double*>(ldlt.factor->x);
  for (std::size_t j = 0; j < ldlt.factor->n; ++j)
    if (x[p[j]] < 0.0) ++result.negative_pivots;
  result.success = true;
  result.message = "matrix is not positive definite; used LDL^T (" + std::to_string(result.negative_pivots) +
                   " negative pivots)";
  impl_->active = &ldlt;
  return result;
}

double SparseCholesky::factorization_flops() const { return impl_->llt.flops; }
double SparseCholesky::factor_nonzeros() const { return impl_->llt.nonzeros; }

bool SparseCholesky::has_factor() const { return impl_->active != nullptr; }
bool SparseCholesky::is_ldlt() const { return impl_->active == impl_->ldlt.get() && impl_->active; }

void SparseCholesky::set_low_rank_update(const Matrix& F, const Matrix& G) {
  if (!impl_->active) throw std::logic_error("SparseCholesky::set_low_rank_update: no successful factorization");
  if (F.rows() != rows_ || G.rows() != F.cols() || G.cols() != F.cols())
    throw std::invalid_argument("SparseCholesky::set_low_rank_update: F must be n x k and G k x k");
  low_rank_factors_.resize(rows_, 0);
  if (F.cols() == 0) return;
  low_rank_solved_ = base_solve(F);
  const Matrix capacitance = Matrix::Identity(F.cols(), F.cols()) + G * (F.transpose() * low_rank_solved_);
  capacitance_.compute(capacitance);
  if (!(capacitance_.rcond() > 1e-14))
    throw std::runtime_error("SparseCholesky::set_low_rank_update: the capacitance matrix is singular");
  low_rank_core_ = G;
  low_rank_factors_ = F;
}

Matrix SparseCholesky::solve_columns(const Matrix& b) const {
  Matrix x = base_solve(b);
  if (has_low_rank_update())
    x -= low_rank_solved_ * capacitance_.solve(low_rank_core_ * (low_rank_factors_.transpose() * x));
  return x;
}

Matrix SparseCholesky::base_solve(const Matrix& b) const {
  if (!impl_->active) throw std::logic_error("SparseCholesky::solve: no successful factorization");
  if (b.rows() != rows_) throw std::invalid_argument("SparseCholesky::solve: right-hand side has the wrong size");
  CholmodFactor& f = *impl_->active;
  const FactorizationThreadsGuard threads;
  // Block solves (BLAS-3 panels) keep the BLAS threads: with 64 columns they are 1.2x faster
  // with two than with one; with one or two columns the second thread costs more than it gives.
  const SerialBlasGuard serial_blas(b.cols() < 4);
  back_solves_ += static_cast<long>(b.cols());
  cholmod_dense rhs = view(b.data(), b.rows(), b.cols());
  cholmod_dense* sol = cholmod_solve(CHOLMOD_A, f.factor, &rhs, &f.common);
  if (!sol) throw std::runtime_error("CHOLMOD solve failed (status " + std::to_string(f.common.status) + ")");
  Matrix out = Eigen::Map<const Matrix>(static_cast<const double*>(sol->x), b.rows(), b.cols());
  cholmod_free_dense(&sol, &f.common);
  return out;
}

Vector SparseCholesky::solve(const Vector& b) const {
  const Matrix m = solve_columns(Matrix(b));
  return m.col(0);
}

}  // namespace tailor
