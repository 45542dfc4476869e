#!/usr/bin/env bash
# Installs what tailor needs to build and test on Debian 12. Safe to re-run: it asks apt only
# for missing packages (and refreshes the package lists only then), so once everything is in
# place it needs neither root nor the network.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  # Build speed (docs/testing.md, "Build time"): Ninja, and a compiler cache that a fresh clone in
  # another folder reuses.
  ninja-build ccache
  libeigen3-dev libsuitesparse-dev coinor-libipopt-dev libnlopt-cxx-dev libarpack2-dev libceres-dev
  nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev
  libpng-dev
  # tailor studio's server (problems/studio, docs/studio.md): Debian's cpp-httplib is a header of
  # declarations and a shared library, so the studio adds little to the quick start's build.
  libcpp-httplib-dev
  # METIS: partitions meshes into domains for the domain-decomposed reduced models
  # (forward/reduction/domain_partition.cpp, docs/reduction.md).
  libmetis-dev
  # The Python module (python/, docs/python.md) and its tests; python3-matplotlib is optional
  # (examples/python plots with it when it is there).
  pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest
  # The optional PETSc back-end (TAILOR_WITH_PETSC, docs/petsc.md): PETSc 3.18 with OpenMPI.
  petsc-dev openmpi-bin
  # CHOLMOD's speed is BLAS's speed: OpenBLAS must provide libblas.so.3 (see below).
  libopenblas0-pthread libopenblas-pthread-dev
)
# `install-deps.sh sanitizers` (CI): also clang with its sanitizer and libFuzzer runtimes, LLVM's
# OpenMP and llvm-symbolizer (for scripts/sanitize.sh and scripts/fuzz.sh), and the optional
# Python packages whose tests are skipped without them: PyTorch (python/tailor/torch.py), meshio
# and matplotlib (python/tailor/fields.py), mypy (stubtest of python/tailor/_tailor.pyi), nbclient,
# nbformat and ipykernel (examples/python/inverse_design.ipynb, run headless); the quick start
# does not wait for their ~260 packages.
if [[ ${1:-} == sanitizers ]]; then
  packages+=(clang-14 libclang-rt-14-dev libomp-14-dev llvm-14
            python3-torch python3-meshio python3-matplotlib python3-mypy
            python3-nbclient python3-nbformat python3-ipykernel)
  # tailor studio's browser test (studio/web/test/browser_test.mjs): headless chromium driven by
  # npm's puppeteer-core; Node and npm from Debian unless a Node with npm is installed already.
  packages+=(chromium)
  command -v npm >/dev/null || packages+=(nodejs npm)
fi

as_root() {
  if [[ ${EUID} -eq 0 ]]; then "$@"; else sudo "$@"; fi
}

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "${package}" 2>/dev/null || true)
  [[ ${status} == installed ]] || missing+=("${package}")
done

if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  as_root apt-get update
  as_root apt-get install -y --no-install-recommends "${missing[@]}"
fi

# libceres-dev pulls in ATLAS, which also registers itself for libblas.so.3/liblapack.so.3.
# OpenBLAS has the higher priority and wins in auto mode, but a manual selection would
# survive: pin OpenBLAS explicitly whenever something else is active.
for library in libblas.so.3 liblapack.so.3; do
  while read -r name _ current; do
    [[ ${current} == */openblas-pthread/* ]] && continue
    openblas=$(update-alternatives --list "${name}" | grep /openblas-pthread/)
    echo "install-deps: ${name} pointed to ${current}; selecting ${openblas}"
    as_root update-alternatives --set "${name}" "${openblas}"
  done < <(update-alternatives --get-selections | grep "^${library//./\\.}-")
done
