#!/usr/bin/env bash
# Installs the dependencies, builds tailor in build/ (Release, warnings are errors; the same
# configuration as quickstart.sh, so a build from the quick start is reused) and runs the whole
# test suite. Exits with ctest's status.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/configure.sh
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
