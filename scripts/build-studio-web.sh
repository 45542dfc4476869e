#!/usr/bin/env bash
# Builds tailor studio's page (studio/web, docs/studio.md) into build/share/tailor/studio, where
# bin/tailor finds it and `cmake --install` installs it from: `npm ci` (three.js and, for the
# browser test, puppeteer-core, at the versions package-lock.json pins), then studio/web/build.mjs.
# Needs Node >= 18 and npm; users of a built or installed tailor need neither. Usage:
#   bash scripts/build-studio-web.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build_dir=$(realpath -m "${1:-build}")
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
  echo "build-studio-web: Node and npm are not installed; the studio's page is not built" >&2
  exit 1
fi
# npm ci again only when the lock file changed since the last install.
if [[ ! -f studio/web/node_modules/.package-lock.json ||
      studio/web/package-lock.json -nt studio/web/node_modules/.package-lock.json ]]; then
  (cd studio/web && npm ci --no-audit --no-fund)
fi
node studio/web/build.mjs "${build_dir}/share/tailor/studio"
