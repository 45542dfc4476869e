#!/usr/bin/env bash
# Installs the dependencies and configures build/ (Release, warnings are errors). Shared by
# quickstart.sh and test.sh so that both use one build: after the quick start, the tests only
# need building what is left. The libraries build in batches (TAILOR_UNITY_BUILD, a clean build's
# fastest form); for incremental work pass -DTAILOR_UNITY_BUILD=OFF. Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DTAILOR_WERROR=ON -DTAILOR_UNITY_BUILD=ON "$@"
