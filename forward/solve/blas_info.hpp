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

// The kernel set OpenBLAS runs in this process ("Haswell", "SkylakeX", ...; openblas_get_corename),
// empty when the BLAS is not OpenBLAS.
std::string blas_core();

// OpenBLAS built for several CPUs (Debian's is) picks its kernels once, when it loads, from the
// CPU's family and model numbers. A CPU its table does not know, such as a virtual machine's
// generic "Intel Xeon Processor", gets the oldest x86-64 kernels ("Prescott", SSE3) even when it
// has AVX-512: dgemm then runs at 4.0 instead of 18.5 GFLOP/s on one core (1500 x 1500), and every
// CHOLMOD factorization with it (docs/performance.md, "BLAS kernels"). OPENBLAS_CORETYPE names
// the kernels to use instead, but OpenBLAS reads it only when it loads.
//
// The kernels this CPU can run: "SkylakeX" with AVX-512 (F, CD, BW, DQ, VL), "Haswell" with AVX2
// and FMA, "Sandybridge" with AVX, else empty.
std::string cpu_blas_core();

// For a program's main(), before anything else: when OPENBLAS_CORETYPE is unset and OpenBLAS
// runs kernels of an older instruction set than cpu_blas_core() (only the SSE and AVX kernels
// are counted as older, so a core OpenBLAS recognised is never overridden), sets
// OPENBLAS_CORETYPE to cpu_blas_core() and executes the program again (/proc/self/exe, the same
// arguments and environment otherwise). Returns without doing anything when there is nothing to
// do, when TAILOR_BLAS_REEXEC is set (the re-executed process), or when exec fails. Setting
// OPENBLAS_CORETYPE (to any value) keeps what the user chose.
void use_cpu_blas_core(char** argv);

}  // namespace tailor
