#pragma once
// Wall-clock timing of the parts of a run: seconds on the steady clock since t0.
#include <chrono>

namespace tailor {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace tailor
