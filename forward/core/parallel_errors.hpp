#pragma once
// Exceptions out of OpenMP parallel regions. An exception that leaves a parallel region calls
// std::terminate (in a test binary, a Python interpreter or a notebook kernel alike), so a loop
// whose body can throw (a material refusing its parameters, a kernel checking its input) catches
// per iteration, and rethrows after the region the exception of the lowest iteration that threw:
// the same error for every thread count.
//
//   FirstError errors;
//   #pragma omp parallel for
//   for (int j = 0; j < n; ++j) {
//     try { work(j); } catch (...) { errors.capture(j); }
//   }
//   errors.rethrow();
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>

namespace tailor {

class FirstError {
 public:
  // From a catch block: keeps the current exception if `iteration` is the lowest so far.
  void capture(std::ptrdiff_t iteration) noexcept {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (iteration < iteration_) {
      iteration_ = iteration;
      error_ = std::current_exception();
    }
  }
  // After the region: rethrows the kept exception, if any.
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::ptrdiff_t iteration_ = std::numeric_limits<std::ptrdiff_t>::max();
  std::exception_ptr error_;
};

}  // namespace tailor
