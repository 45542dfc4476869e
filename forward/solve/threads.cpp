#include "forward/solve/threads.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "forward/solve/blas_info.hpp"

namespace tailor {
namespace {

ThreadSettings& settings_storage() {
  static ThreadSettings settings;
  return settings;
}

// OpenBLAS's thread controls, looked up at run time: the BLAS is whatever library provides
// libblas.so.3 in this process (see blas_info.hpp), so they may be absent.
using SetThreads = void (*)(int);
using GetThreads = int (*)();
SetThreads openblas_set() {
  return reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
}
GetThreads openblas_get() {
  return reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
}

// The num_threads clause Debian's CHOLMOD 5.12 was compiled with (CHOLMOD_OMP_NUM_THREADS).
constexpr int kCholmodCompiledThreads = 4;

}  // namespace

void set_thread_settings(const ThreadSettings& settings) {
  if (settings.assembly < 0 || settings.blas < 0)
    throw std::invalid_argument("thread counts must be >= 0 (0 = the library's default)");
  if (settings.factorization != 0 && settings.factorization != 1)
    throw std::invalid_argument(
        "factorization threads must be 1 (CHOLMOD's OpenMP regions serialized) or 0 "
        "(as CHOLMOD was built); got " +
        std::to_string(settings.factorization));
  // 0 restores what the process started with, which honours OMP_NUM_THREADS and
  // OPENBLAS_NUM_THREADS (each runtime's default is the number of cores without them). The
  // values are read before the first change, so later calls cannot lose them.
  static const int initial_assembly = omp_get_max_threads();
  static const int initial_blas = openblas_get() ? openblas_get()() : 0;
  omp_set_num_threads(settings.assembly > 0 ? settings.assembly : initial_assembly);
  if (const SetThreads set = openblas_set()) set(settings.blas > 0 ? settings.blas : initial_blas);
  settings_storage() = settings;
}

const ThreadSettings& thread_settings() { return settings_storage(); }

ThreadReport current_threads() {
  ThreadReport report;
  report.assembly = omp_get_max_threads();
  if (const GetThreads get = openblas_get()) report.blas = get();
  report.factorization = thread_settings().factorization == 1 ? 1 : kCholmodCompiledThreads;
  report.blas_library = blas_library_path();
  report.blas_core = blas_core();
  return report;
}

int process_thread_count() {
  std::error_code error;
  int count = 0;
  for (std::filesystem::directory_iterator it("/proc/self/task", error), end; !error && it != end;
       it.increment(error))
    ++count;
  return error ? -1 : count;
}

FactorizationThreadsGuard::FactorizationThreadsGuard() {
  if (thread_settings().factorization != 1) return;
  saved_levels_ = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
}

FactorizationThreadsGuard::~FactorizationThreadsGuard() {
  if (saved_levels_ >= 0) omp_set_max_active_levels(saved_levels_);
}

SerialBlasGuard::SerialBlasGuard(bool active) {
  if (!active) return;
  const GetThreads get = openblas_get();
  const SetThreads set = openblas_set();
  if (!get || !set) return;
  const int threads = get();
  if (threads <= 1) return;
  saved_threads_ = threads;
  set(1);
}

SerialBlasGuard::~SerialBlasGuard() {
  if (saved_threads_ > 0) openblas_set()(saved_threads_);
}

}  // namespace tailor
