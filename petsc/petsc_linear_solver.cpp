#include "petsc/petsc_linear_solver.hpp"

#include <petscksp.h>

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace tailor {
namespace {

// PETSc's error handler: keep the first message (the one with the reason) for the exception,
// and print nothing (the exception carries it).
std::string& last_petsc_error() {
  static std::string message;
  return message;
}

PetscErrorCode keep_error(MPI_Comm, int, const char* function, const char*, PetscErrorCode code,
                          PetscErrorType type, const char* message, void*) {
  if (type == PETSC_ERROR_INITIAL)
    last_petsc_error() = std::string(message ? message : "") + " (in " + (function ? function : "?") + ")";
  return code;
}

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  std::string message = std::string("PETSc: ") + what + " failed: " + (text ? text : "error");
  if (!last_petsc_error().empty()) message += ": " + last_petsc_error();
  last_petsc_error().clear();
  throw std::runtime_error(message);
}

// The option names ("-ksp_type") in an options string.
std::vector<std::string> option_names(const std::string& options) {
  std::vector<std::string> names;
  std::istringstream in(options);
  for (std::string token; in >> token;)
    if (token.size() > 1 && token[0] == '-' && !(token[1] >= '0' && token[1] <= '9') && token[1] != '.')
      names.push_back(token);
  return names;
}

}  // namespace

PetscSession::PetscSession(int* argc, char*** argv) {
  PetscBool initialized = PETSC_FALSE;
  check(PetscInitialized(&initialized), "PetscInitialized");
  if (initialized) return;
  check(PetscInitialize(argc, argv, nullptr, nullptr), "PetscInitialize");
  owns_ = true;
  check(PetscPushErrorHandler(keep_error, nullptr), "PetscPushErrorHandler");
}

PetscSession::~PetscSession() {
  if (owns_) PetscFinalize();
}

int PetscSession::rank() {
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

int PetscSession::size() {
  int s = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &s);
  return s;
}

struct PetscLinearSolver::Impl {
  KSP ksp = nullptr;
  Mat matrix = nullptr;
  Vec x = nullptr, b = nullptr, gathered = nullptr;
  VecScatter scatter = nullptr;
  PetscInt n = 0, row_begin = 0, row_end = 0;
  PetscReal default_rtol = 0, abstol = 0, dtol = 0;
  PetscInt max_iterations = 0;
  Eigen::SparseMatrix<double, Eigen::RowMajor> full;  // the whole symmetric matrix (every rank)
  bool options_checked = false;
  std::vector<std::string> inserted;  // option names this solver put into PETSc's database
  int dim = 0;                        // with vertex coordinates: the block size
  Vector coordinates;
  bool near_null_space = false;       // of the current matrix
  bool by_parts = false;              // assemble_by_parts (options or -tailor_assemble_by_parts)
  bool shared = false;                // the current matrix is a sum of shares (`full` is empty)
  std::uint64_t coo_pattern = 0;  // a hash of this rank's COO pattern of the current matrix
  std::size_t coo_count = 0;      // and its length

  // PETSc's default split (PetscSplitOwnership) of n rows, by whole vertices (block size dim)
  // when the coordinates of all n unknowns are known: the first count % size ranks get one more.
  struct Split {
    PetscInt block = 1, begin = 0, local = 0;
  };
  Split split(PetscInt n, int rank, int size) const {
    Split out;
    const bool blocked = dim > 0 && coordinates.size() == n && n % dim == 0;
    out.block = blocked ? dim : 1;
    const PetscInt count = n / out.block, base = count / size, extra = count % size;
    out.local = out.block * (base + (rank < extra ? 1 : 0));
    out.begin = out.block * (rank * base + std::min<PetscInt>(rank, extra));
    return out;
  }
  bool blocked(PetscInt n) const { return dim > 0 && coordinates.size() == n && n % dim == 0; }
  // New matrix (sizes, block size, symmetric and SPD flags), vectors, the near-null space
  // from the coordinates when blocked, and the gather of solutions. Preallocation is the caller's.
  void create_matrix(PetscInt n, const Split& s);
  // After the values are in: the KSP's operators and its set-up.
  void finish_setup(PetscInt n, const Split& s);
  int solves = 0;
  long long iterations = 0;
  std::vector<int> recent_iterations;
  LinearSolveStats last;

  void destroy_matrix() {
    if (scatter) VecScatterDestroy(&scatter);
    if (gathered) VecDestroy(&gathered);
    if (x) VecDestroy(&x);
    if (b) VecDestroy(&b);
    if (matrix) MatDestroy(&matrix);
  }
  ~Impl() {
    destroy_matrix();
    if (ksp) KSPDestroy(&ksp);
    // The next solver starts from the command line's options again.
    for (const std::string& name : inserted) PetscOptionsClearValue(nullptr, name.c_str());
  }
};

PetscLinearSolver::PetscLinearSolver(PetscSolverOptions options)
    : impl_(std::make_unique<Impl>()), options_(std::move(options)) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) throw std::logic_error("PetscLinearSolver: PETSc is not initialized (construct a PetscSession first)");
  if (!(options_.relative_tolerance > 0.0 && options_.relative_tolerance < 1.0))
    throw std::invalid_argument("PetscLinearSolver: relative_tolerance must be in (0, 1)");
  if (options_.max_iterations < 1) throw std::invalid_argument("PetscLinearSolver: max_iterations must be >= 1");
  try {
    impl_->inserted = option_names(options_.options);
    if (!options_.options.empty())
      check(PetscOptionsInsertString(nullptr, options_.options.c_str()), "reading the PETSc options");
    check(KSPCreate(PETSC_COMM_WORLD, &impl_->ksp), "KSPCreate");
    check(KSPSetType(impl_->ksp, KSPCG), "KSPSetType");
    PC pc = nullptr;
    check(KSPGetPC(impl_->ksp, &pc), "KSPGetPC");
    check(PCSetType(pc, PCGAMG), "PCSetType");
    check(KSPSetNormType(impl_->ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    check(KSPSetTolerances(impl_->ksp, options_.relative_tolerance, PETSC_DEFAULT, PETSC_DEFAULT,
                           options_.max_iterations),
          "KSPSetTolerances");
    check(KSPSetFromOptions(impl_->ksp), "KSPSetFromOptions");
    check(KSPGetTolerances(impl_->ksp, &impl_->default_rtol, &impl_->abstol, &impl_->dtol, &impl_->max_iterations),
          "KSPGetTolerances");
    PetscBool by_parts = options_.assemble_by_parts ? PETSC_TRUE : PETSC_FALSE;
    check(PetscOptionsGetBool(nullptr, nullptr, "-tailor_assemble_by_parts", &by_parts, nullptr),
          "reading -tailor_assemble_by_parts");
    impl_->by_parts = by_parts == PETSC_TRUE;
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(std::string("petsc_options \"") + options_.options + "\": " + e.what());
  }
}

PetscLinearSolver::~PetscLinearSolver() = default;

bool PetscLinearSolver::is_root() const { return PetscSession::rank() == 0; }

std::string PetscLinearSolver::method() const {
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  PC pc = nullptr;
  KSPGetType(impl_->ksp, &ksp_type);
  KSPGetPC(impl_->ksp, &pc);
  PCGetType(pc, &pc_type);
  return std::string(ksp_type ? ksp_type : "?") + "/" + (pc_type ? pc_type : "?");
}

void PetscLinearSolver::Impl::create_matrix(PetscInt n, const Split& s) {
  destroy_matrix();
  check(MatCreate(PETSC_COMM_WORLD, &matrix), "MatCreate");
  check(MatSetSizes(matrix, s.local, s.local, n, n), "MatSetSizes");
  check(MatSetBlockSize(matrix, s.block), "MatSetBlockSize");
  check(MatSetType(matrix, MATMPIAIJ), "MatSetType");
  check(MatCreateVecs(matrix, &x, &b), "MatCreateVecs");
  near_null_space = false;
  if (blocked(n)) {
    // The rigid-body modes from this rank's vertices (the vector's block size is dim).
    Vec local_coordinates = nullptr;
    check(VecDuplicate(x, &local_coordinates), "VecDuplicate");
    PetscScalar* c = nullptr;
    check(VecGetArray(local_coordinates, &c), "VecGetArray");
    std::copy(coordinates.data() + s.begin, coordinates.data() + s.begin + s.local, c);
    check(VecRestoreArray(local_coordinates, &c), "VecRestoreArray");
    MatNullSpace modes = nullptr;
    const PetscErrorCode built = MatNullSpaceCreateRigidBody(local_coordinates, &modes);
    VecDestroy(&local_coordinates);
    check(built, "MatNullSpaceCreateRigidBody");
    const PetscErrorCode attached = MatSetNearNullSpace(matrix, modes);
    MatNullSpaceDestroy(&modes);
    check(attached, "MatSetNearNullSpace");
    near_null_space = true;
  }
  check(VecScatterCreateToAll(x, &scatter, &gathered), "VecScatterCreateToAll");
}

void PetscLinearSolver::Impl::finish_setup(PetscInt size_n, const Split& s) {
  check(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption(MAT_SYMMETRIC)");
  check(MatSetOption(matrix, MAT_SPD, PETSC_TRUE), "MatSetOption(MAT_SPD)");
  check(KSPSetOperators(ksp, matrix, matrix), "KSPSetOperators");
  check(KSPSetUp(ksp), "KSPSetUp");
  n = size_n;
  row_begin = s.begin;
  row_end = s.begin + s.local;
}

bool PetscLinearSolver::setup(const SparseMatrix& upper, std::string& message) {
  try {
    Impl& m = *impl_;
    const PetscInt n = static_cast<PetscInt>(upper.rows());
    m.full = upper.selfadjointView<Eigen::Upper>();
    m.full.makeCompressed();
    m.shared = false;
    const Impl::Split s = m.split(n, PetscSession::rank(), PetscSession::size());
    const PetscInt begin = s.begin, local = s.local;
    std::vector<PetscInt> row_start(local + 1), columns;
    std::vector<PetscScalar> values;
    const auto* outer = m.full.outerIndexPtr();
    for (PetscInt i = 0; i < local; ++i) row_start[i] = static_cast<PetscInt>(outer[begin + i] - outer[begin]);
    row_start[local] = static_cast<PetscInt>(outer[begin + local] - outer[begin]);
    columns.assign(m.full.innerIndexPtr() + outer[begin], m.full.innerIndexPtr() + outer[begin + local]);
    values.assign(m.full.valuePtr() + outer[begin], m.full.valuePtr() + outer[begin + local]);
    m.create_matrix(n, s);
    check(MatMPIAIJSetPreallocationCSR(m.matrix, row_start.data(), columns.data(), values.data()),
          "MatMPIAIJSetPreallocationCSR");
    m.finish_setup(n, s);
    return true;
  } catch (const std::runtime_error& e) {
    message = e.what();
    return false;
  }
}

bool PetscLinearSolver::assembles_by_parts() const { return impl_->by_parts; }

bool PetscLinearSolver::owns_unknown(int unknown, int num_unknowns) const {
  const Impl::Split s = impl_->split(num_unknowns, PetscSession::rank(), PetscSession::size());
  return unknown >= s.begin && unknown < s.begin + s.local;
}

bool PetscLinearSolver::setup_share(const SparseMatrix& upper, std::string& message) {
  try {
    Impl& m = *impl_;
    const PetscInt n = static_cast<PetscInt>(upper.rows());
    if (upper.cols() != n) throw std::runtime_error("the Hessian share is not square");
    const Impl::Split s = m.split(n, PetscSession::rank(), PetscSession::size());
    // COO triplets: both triangles of the share, and a (zero) diagonal entry for every owned
    // row, so that each owned row has its diagonal whichever ranks' elements fill it.
    std::vector<PetscInt> rows, columns;
    std::vector<PetscScalar> values;
    const std::size_t count = 2 * static_cast<std::size_t>(upper.nonZeros()) + static_cast<std::size_t>(s.local);
    rows.reserve(count);
    columns.reserve(count);
    values.reserve(count);
    for (int j = 0; j < upper.outerSize(); ++j)
      for (SparseMatrix::InnerIterator e(upper, j); e; ++e) {
        if (e.row() > j) continue;  // upper triangle only
        rows.push_back(e.row());
        columns.push_back(j);
        values.push_back(e.value());
        if (e.row() != j) {
          rows.push_back(j);
          columns.push_back(e.row());
          values.push_back(e.value());
        }
      }
    for (PetscInt i = s.begin; i < s.begin + s.local; ++i) {
      rows.push_back(i);
      columns.push_back(i);
      values.push_back(0.0);
    }
    // A new pattern on any rank makes every rank preallocate again (collective). The pattern is
    // compared by its length and a hash (FNV-1a over the indices), not kept: at a million tets
    // its index arrays would be ~0.7 GB per rank for nothing else.
    std::uint64_t hash = 1469598103934665603ULL;
    for (std::size_t k = 0; k < rows.size(); ++k)
      hash = ((hash ^ static_cast<std::uint64_t>(rows[k])) * 1099511628211ULL ^ static_cast<std::uint64_t>(columns[k])) *
             1099511628211ULL;
    int same = m.matrix && m.shared && m.n == n && m.coo_count == rows.size() && m.coo_pattern == hash ? 1 : 0;
    int all_same = 0;
    if (MPI_Allreduce(&same, &all_same, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD) != MPI_SUCCESS)
      throw std::runtime_error("MPI_Allreduce failed");
    m.full = {};
    if (!all_same) {
      m.create_matrix(n, s);
      // (PETSc may overwrite the index arrays; they are not needed after this.)
      check(MatSetPreallocationCOO(m.matrix, static_cast<PetscCount>(rows.size()), rows.data(), columns.data()),
            "MatSetPreallocationCOO");
      m.coo_count = rows.size();
      m.coo_pattern = hash;
      m.shared = true;
    }
    std::vector<PetscInt>().swap(rows);  // before GAMG's set-up allocates its hierarchy
    std::vector<PetscInt>().swap(columns);
    check(MatSetValuesCOO(m.matrix, values.data(), INSERT_VALUES), "MatSetValuesCOO");
    std::vector<PetscScalar>().swap(values);
    m.finish_setup(n, s);
    return true;
  } catch (const std::runtime_error& e) {
    impl_->shared = false;
    message = e.what();
    return false;
  }
}

bool PetscLinearSolver::matrix_norms(double& inf_norm, double& max_abs_diagonal, double& min_abs_diagonal) const {
  const Impl& m = *impl_;
  if (!m.matrix) return false;
  PetscReal norm = 0.0;
  if (MatNorm(m.matrix, NORM_INFINITY, &norm) != 0) return false;
  Vec diagonal = nullptr;
  if (VecDuplicate(m.x, &diagonal) != 0) return false;
  PetscReal largest = 0.0, smallest = 0.0;
  const bool ok = MatGetDiagonal(m.matrix, diagonal) == 0 && VecAbs(diagonal) == 0 &&
                  VecMax(diagonal, nullptr, &largest) == 0 && VecMin(diagonal, nullptr, &smallest) == 0;
  VecDestroy(&diagonal);
  if (!ok) return false;
  inf_norm = norm;
  max_abs_diagonal = largest;
  min_abs_diagonal = smallest;
  return true;
}

Vector PetscLinearSolver::multiply(const Vector& in) const {
  const Impl& m = *impl_;
  if (!m.matrix) throw std::logic_error("PetscLinearSolver::multiply before setup");
  if (in.size() != m.n) throw std::invalid_argument("PetscLinearSolver::multiply: vector of the wrong size");
  PetscScalar* local = nullptr;
  check(VecGetArray(m.x, &local), "VecGetArray");
  std::copy(in.data() + m.row_begin, in.data() + m.row_end, local);
  check(VecRestoreArray(m.x, &local), "VecRestoreArray");
  Vec product = nullptr;
  check(VecDuplicate(m.b, &product), "VecDuplicate");
  check(MatMult(m.matrix, m.x, product), "MatMult");
  check(VecScatterBegin(m.scatter, product, m.gathered, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
  check(VecScatterEnd(m.scatter, product, m.gathered, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
  VecDestroy(&product);
  const PetscScalar* all = nullptr;
  check(VecGetArrayRead(m.gathered, &all), "VecGetArrayRead");
  Vector out = Eigen::Map<const Vector>(all, m.n);
  check(VecRestoreArrayRead(m.gathered, &all), "VecRestoreArrayRead");
  return out;
}

LinearSolveStats PetscLinearSolver::solve(const Vector& rhs, double relative_tolerance, Vector& solution) {
  Impl& m = *impl_;
  if (!m.matrix) throw std::logic_error("PetscLinearSolver::solve before setup");
  if (rhs.size() != m.n) throw std::invalid_argument("PetscLinearSolver::solve: right-hand side of the wrong size");
  LinearSolveStats stats;
  stats.relative_tolerance = relative_tolerance > 0.0 ? relative_tolerance : m.default_rtol;
  check(KSPSetTolerances(m.ksp, stats.relative_tolerance, m.abstol, m.dtol, m.max_iterations), "KSPSetTolerances");
  PetscScalar* local = nullptr;
  check(VecGetArray(m.b, &local), "VecGetArray");
  std::copy(rhs.data() + m.row_begin, rhs.data() + m.row_end, local);
  check(VecRestoreArray(m.b, &local), "VecRestoreArray");
  check(KSPSolve(m.ksp, m.b, m.x), "KSPSolve");
  KSPConvergedReason reason;
  PetscInt iterations = 0;
  check(KSPGetConvergedReason(m.ksp, &reason), "KSPGetConvergedReason");
  check(KSPGetIterationNumber(m.ksp, &iterations), "KSPGetIterationNumber");
  check(VecScatterBegin(m.scatter, m.x, m.gathered, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
  check(VecScatterEnd(m.scatter, m.x, m.gathered, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
  const PetscScalar* all = nullptr;
  check(VecGetArrayRead(m.gathered, &all), "VecGetArrayRead");
  solution = Eigen::Map<const Vector>(all, m.n);
  check(VecRestoreArrayRead(m.gathered, &all), "VecRestoreArrayRead");
  if (!m.options_checked) {
    // Every option of the string must have been read by now (KSP, PC, the factorization).
    m.options_checked = true;
    PetscInt count = 0;
    char** names = nullptr;
    char** values = nullptr;
    check(PetscOptionsLeftGet(nullptr, &count, &names, &values), "PetscOptionsLeftGet");
    std::string unused;
    for (PetscInt k = 0; k < count; ++k) {
      const std::string name = names[k][0] == '-' ? names[k] : std::string("-") + names[k];
      if (std::find(m.inserted.begin(), m.inserted.end(), name) != m.inserted.end()) unused = name;
    }
    PetscOptionsLeftRestore(nullptr, &count, &names, &values);
    if (!unused.empty())
      throw std::invalid_argument("petsc_options \"" + options_.options + "\": option " + unused +
                                  " is not one that the solver (" + method() + ") reads");
  }
  // The true relative residual, in double precision on the whole matrix (every rank has it;
  // with shares, PETSc's distributed product: b - A x).
  const double b_norm = rhs.norm();
  double r_norm = 0.0;
  if (m.shared) {
    Vec residual = nullptr;
    check(VecDuplicate(m.b, &residual), "VecDuplicate");
    PetscReal norm = 0.0;
    const PetscErrorCode code = MatMult(m.matrix, m.x, residual) || VecAYPX(residual, -1.0, m.b) ||
                                VecNorm(residual, NORM_2, &norm);
    VecDestroy(&residual);
    check(code, "the residual b - A x");
    r_norm = norm;
  } else {
    r_norm = (rhs - m.full * solution).norm();
  }
  stats.relative_residual = b_norm > 0.0 ? r_norm / b_norm : r_norm;
  stats.iterations = static_cast<int>(iterations);
  stats.converged = reason > 0 && solution.allFinite();
  ++m.solves;
  m.iterations += iterations;
  m.recent_iterations.push_back(stats.iterations);
  constexpr std::size_t kRecent = 8;
  if (m.recent_iterations.size() > kRecent) m.recent_iterations.erase(m.recent_iterations.begin());
  if (!stats.converged) {
    std::ostringstream why;
    why << method() << " stopped with " << KSPConvergedReasons[reason] << " after " << iterations
        << " iterations (relative residual " << stats.relative_residual << ", tolerance " << stats.relative_tolerance
        << ")";
    stats.message = why.str();
  }
  m.last = stats;
  return stats;
}

void PetscLinearSolver::set_vertex_coordinates(int dim, const Vector& coordinates) {
  if (dim < 1 || dim > 3 || coordinates.size() % dim != 0)
    throw std::invalid_argument("PetscLinearSolver::set_vertex_coordinates: dim must be 1, 2 or 3 and divide the "
                                "number of coordinates");
  impl_->dim = dim;
  impl_->coordinates = coordinates;
}

LinearSolverInfo PetscLinearSolver::info() const {
  const Impl& m = *impl_;
  LinearSolverInfo i;
  i.name = name();
  i.options = options_.options;
  char* all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) == 0 && all) {
    i.options_in_effect = all;
    PetscFree(all);
  }
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  PC pc = nullptr;
  KSPGetType(m.ksp, &ksp_type);
  KSPGetPC(m.ksp, &pc);
  PCGetType(pc, &pc_type);
  i.krylov_method = ksp_type ? ksp_type : "";
  i.preconditioner = pc_type ? pc_type : "";
  PetscBool factorization = PETSC_FALSE;
  PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factorization, PCLU, PCCHOLESKY, PCILU, PCICC, "");
  if (factorization) {
    MatSolverType package = nullptr;
    if (PCFactorGetMatSolverType(pc, &package) == 0 && package) i.factorization_package = package;
  }
  PetscReal rtol = 0, abstol = 0, dtol = 0;
  PetscInt max_it = 0;
  KSPGetTolerances(m.ksp, &rtol, &abstol, &dtol, &max_it);
  i.relative_tolerance = m.default_rtol;
  i.absolute_tolerance = abstol;
  i.divergence_tolerance = dtol;
  i.max_iterations = static_cast<int>(max_it);
  i.processes = PetscSession::size();
  i.assembles_by_parts = m.by_parts;
  i.near_null_space = m.near_null_space;
  i.solves = m.solves;
  i.iterations = m.iterations;
  i.recent_iterations = m.recent_iterations;
  i.last = m.last;
  return i;
}

}  // namespace tailor
