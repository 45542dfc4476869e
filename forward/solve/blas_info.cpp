#include "forward/solve/blas_info.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string_view>
#include <system_error>

// The Fortran BLAS entry point; only its address is taken, so the signature is irrelevant.
extern "C" void dgemm_();

namespace tailor {

std::string blas_library_path() {
  // Taking the address goes through the same global symbol lookup that binds CHOLMOD's
  // calls, so the object found here is the one doing CHOLMOD's dense work.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&dgemm_), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code error;
  const std::filesystem::path resolved = std::filesystem::canonical(info.dli_fname, error);
  return error ? std::string(info.dli_fname) : resolved.string();
}

namespace {

// Instruction-set level of an OpenBLAS x86-64 core name: 0 SSE, 1 AVX, 2 AVX2, 3 AVX-512; -1 for
// names not listed (other architectures, future cores): those are never overridden.
int core_level(std::string_view core) {
  for (std::string_view sse : {"Prescott", "Core2", "Penryn", "Dunnington", "Nehalem", "Atom", "Barcelona", "Opteron",
                               "Opteron_SSE3", "Bobcat", "Katmai", "Coppermine", "Northwood", "Banias"})
    if (core == sse) return 0;
  if (core == "Sandybridge" || core == "Bulldozer") return 1;
  if (core == "Haswell" || core == "Zen" || core == "Piledriver" || core == "Steamroller" || core == "Excavator")
    return 2;
  if (core == "SkylakeX" || core == "Cooperlake" || core == "SapphireRapids") return 3;
  return -1;
}

}  // namespace

std::string blas_core() {
  using CoreName = char* (*)();
  const auto name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  const char* core = name ? name() : nullptr;
  return core ? std::string(core) : std::string();
}

std::string cpu_blas_core() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
    return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
  if (__builtin_cpu_supports("avx")) return "Sandybridge";
#endif
  return {};
}

void use_cpu_blas_core(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") || std::getenv("TAILOR_BLAS_REEXEC") || !argv || !argv[0]) return;
  const std::string running = blas_core(), wanted = cpu_blas_core();
  const int running_level = core_level(running);
  if (running.empty() || wanted.empty() || running_level < 0 || running_level > 1 ||
      core_level(wanted) <= running_level)
    return;
  if (setenv("OPENBLAS_CORETYPE", wanted.c_str(), 1) != 0 || setenv("TAILOR_BLAS_REEXEC", "1", 1) != 0) return;
  execv("/proc/self/exe", argv);
  // exec failed: go on with the kernels already loaded, and say nothing was changed.
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv("TAILOR_BLAS_REEXEC");
}

}  // namespace tailor
