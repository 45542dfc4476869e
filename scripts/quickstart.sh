#!/usr/bin/env bash
# From a fresh Debian 12 to a first inverse design: installs the dependencies, builds tailor in
# build/ (Release) and runs a small material design (scenes/cantilever_handle.json): one Young's
# modulus per element of a 480-tet cantilever such that a handle at its tip moves 0.8 under a
# force of 100. Prints one line per optimizer iteration; results (report.json, result.vtu,
# convergence.png, youngs_modulus.png) go to out/quickstart.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/configure.sh
cmake --build build -j"$(nproc)"
build/bin/tailor run scenes/cantilever_handle.json --out out/quickstart
