#!/usr/bin/env bash
# Installs the dependencies, builds tailor in build/ (Release, warnings are errors; the same
# configuration as quickstart.sh, so a build from the quick start is reused) and runs the whole
# test suite. Exits with ctest's status.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/configure.sh
# tailor studio's page and the browser test's npm packages (docs/studio.md), when npm is there;
# without them (or offline) the browser test skips itself.
if command -v npm >/dev/null; then
  bash scripts/build-studio-web.sh build || echo "test.sh: the studio's page was not built; its browser test will skip"
fi
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
