#!/usr/bin/env bash
# Installs clang (Debian's clang 14 with its sanitizer and libFuzzer runtimes) and configures
# build-asan/: every target built with AddressSanitizer and UndefinedBehaviorSanitizer, any
# report fatal, plus the libFuzzer targets of fuzz/. Shared by sanitize.sh and fuzz.sh, which
# build what each needs in it. See docs/testing.md.
#
# Sources build in batches (TAILOR_UNITY_BUILD), with Ninja and through ccache when installed, as
# in the Release build (docs/testing.md, "Build time").
# -O1 keeps the build about as long as the Release one and the instrumented code fast enough;
# line tables (not full debug information) are enough for file:line in every report. Asserts
# stay on (no NDEBUG), so Eigen's index checks run too. Bench programs, the Python module (an
# extension loaded into an uninstrumented interpreter) and the PETSc back-end (MPI's and
# PETSc's own code are not instrumented) are not built.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh sanitizers
generator=()
if [[ ! -f build-asan/CMakeCache.txt ]] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
flags="-O1 -gline-tables-only"
cmake -S . -B build-asan "${generator[@]}" -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS_SANITIZE="${flags}" -DCMAKE_C_FLAGS_SANITIZE="${flags}" \
  -DTAILOR_SANITIZE=address,undefined -DTAILOR_FUZZ=ON -DTAILOR_BUILD_BENCH=OFF -DTAILOR_WITH_PYTHON=OFF \
  -DTAILOR_WITH_PETSC=OFF -DTAILOR_WITH_CUDA=OFF -DTAILOR_UNITY_BUILD=ON "$@"
