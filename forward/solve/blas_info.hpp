#pragma once
// Which BLAS the running process actually uses. Debian lets several BLAS builds (OpenBLAS,
// ATLAS, reference) provide the same Fortran symbols; the dynamic linker binds every
// dgemm_ in the process -- CHOLMOD's included -- to the first library that defines it, and
// that choice sets CHOLMOD's factorization speed (OpenBLAS is ~3x faster than ATLAS here).
#include <string>

namespace tailor {

// Absolute, symlink-resolved path of the shared library that provides `dgemm_` in this
// process, e.g. ".../openblas-pthread/libblas.so.3". Resolving symlinks matters: the loader
// reports the alternatives link (".../libblas.so.3"), which names no vendor. Empty if the
// symbol cannot be attributed to a shared object (e.g. a static BLAS).
std::string blas_library_path();

}  // namespace tailor
