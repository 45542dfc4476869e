#pragma once
// Thread counts of the three parallel layers a solve goes through, and what actually runs.
//
//  assembly       tailor's own OpenMP loops (element energies, gradients, Hessians).
//  blas           OpenBLAS's pthreads, which do CHOLMOD's dense supernodal kernels.
//  factorization  CHOLMOD's own OpenMP loops inside the supernodal factorization.
//
// Why the third one is separate: Debian's CHOLMOD (SuiteSparse 5.12) runs the small loops of
// its supernodal numeric factorization (clearing maps, zeroing each supernode) with a
// compile-time num_threads(4) clause, which neither OMP_NUM_THREADS nor omp_set_num_threads()
// limits. Thousands of such regions per factorization, each waking and parking 4 workers, made
// a factorization 1.4-2.8x slower on 2 cores than running those loops serially while
// OpenBLAS keeps its threads (docs/performance.md). So by default tailor runs CHOLMOD's calls
// with its OpenMP regions serialized (FactorizationThreadsGuard); the BLAS work inside keeps
// the BLAS threads.
#include <string>

namespace tailor {

struct ThreadSettings {
  int assembly = 0;  // OpenMP threads for tailor's loops; 0 = the process's start value
                    // (OMP_NUM_THREADS if set, else the cores)
  int blas = 0;      // OpenBLAS threads; 0 = the start value (OPENBLAS_NUM_THREADS, else cores)
  // CHOLMOD's OpenMP regions: 1 = serialized (default, fastest measured), 0 = as CHOLMOD was
  // built (4 threads in Debian's build). No other count can be imposed on a num_threads
  // clause from outside, so other values are rejected.
  int factorization = 1;
};

// Applies the settings process-wide (omp_set_num_threads, openblas_set_num_threads and the
// factorization mode used by every later SparseCholesky call). Throws std::invalid_argument
// for negative counts or a factorization value other than 0 or 1. Not thread-safe: call it
// before solving, from the thread that solves.
void set_thread_settings(const ThreadSettings& settings);
const ThreadSettings& thread_settings();

// What runs now: OpenMP's max threads, OpenBLAS's thread count (-1 when the BLAS in the
// process is not OpenBLAS), the factorization mode (1 or CHOLMOD's compiled count, 4 with
// Debian's build), the BLAS library's path and OpenBLAS's kernel set.
struct ThreadReport {
  int assembly = 0;
  int blas = -1;
  int factorization = 1;
  std::string blas_library;
  std::string blas_core;  // OpenBLAS's kernels ("SkylakeX", ...; blas_info.hpp); empty if not OpenBLAS
};
ThreadReport current_threads();

// Number of threads of this process now (entries of /proc/self/task); -1 if unreadable.
int process_thread_count();

// Serializes CHOLMOD's OpenMP regions for its lifetime when thread_settings().factorization
// is 1 (by setting OpenMP's max-active-levels to 0, which makes every parallel region run on
// the encountering thread, num_threads clauses included), and restores the previous value.
class FactorizationThreadsGuard {
 public:
  FactorizationThreadsGuard();
  ~FactorizationThreadsGuard();
  FactorizationThreadsGuard(const FactorizationThreadsGuard&) = delete;
  FactorizationThreadsGuard& operator=(const FactorizationThreadsGuard&) = delete;

 private:
  int saved_levels_ = -1;  // -1: nothing to restore
};

// Runs OpenBLAS on one thread for its lifetime when `active`, and restores the previous count.
// For CHOLMOD's back-solves with one or a few right-hand sides (BLAS-2 on small panels): alone
// they gain ~10% from a second BLAS thread, but between tailor's OpenMP loops that thread, still
// spinning (sched_yield) when the loops start, takes a core from them. Serial back-solves made
// the 48k-tet recovery 1.2x and the 6k one 2x faster (docs/performance.md). Does nothing when
// the BLAS is not OpenBLAS or already runs on one thread.
class SerialBlasGuard {
 public:
  explicit SerialBlasGuard(bool active = true);
  ~SerialBlasGuard();
  SerialBlasGuard(const SerialBlasGuard&) = delete;
  SerialBlasGuard& operator=(const SerialBlasGuard&) = delete;

 private:
  int saved_threads_ = -1;  // -1: nothing to restore
};

}  // namespace tailor
