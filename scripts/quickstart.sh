#!/usr/bin/env bash
# From a fresh Debian 12 to a first simulation: installs the dependencies, builds tailor in
# build/ (Release) and runs the command-line tool. Results go to out/quickstart.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
build/bin/tailor simulate --out out/quickstart
