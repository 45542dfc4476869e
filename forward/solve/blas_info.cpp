#include "forward/solve/blas_info.hpp"

#include <dlfcn.h>

#include <filesystem>
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

}  // namespace tailor
