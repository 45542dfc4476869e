#!/usr/bin/env bash
# Installs the dependencies and configures build/ (Release, warnings are errors). Shared by
# quickstart.sh and test.sh so that both use one build: after the quick start, the tests only
# need building what is left. Ninja when installed; sources compiled in batches
# (TAILOR_UNITY_BUILD, a clean build's fastest form; pass -DTAILOR_UNITY_BUILD=OFF for a build
# where an edit recompiles one file); through ccache when installed (cmake/tailorCompilerCache.cmake).
# Extra arguments go to cmake. See docs/testing.md, "Build time".
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh
generator=()
# The generator of an existing build folder cannot change; a new one gets Ninja when present.
if [[ ! -f build/CMakeCache.txt ]] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DTAILOR_WERROR=ON -DTAILOR_UNITY_BUILD=ON "$@"
