// Builds tailor studio's page: copies the page's modules (src/) and three.js (from node_modules,
// pinned by package-lock.json) into one folder of static assets, by default
// ../../build/share/tailor/studio, where bin/tailor finds it and from where it is installed.
// Usage: node build.mjs [OUT_DIR]   (run `npm ci` first; scripts/build-studio-web.sh does both)
import { copyFileSync, mkdirSync, readdirSync, existsSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));

export function buildStudioAssets(outDir = resolve(here, '../../build/share/tailor/studio')) {
  mkdirSync(outDir, { recursive: true });
  for (const file of readdirSync(join(here, 'src'))) copyFileSync(join(here, 'src', file), join(outDir, file));
  const three = join(here, 'node_modules/three/build');
  if (!existsSync(join(three, 'three.module.js'))) throw new Error('three.js is not installed: run `npm ci` in studio/web');
  // three.module.js imports ./three.core.js: both are copied, nothing else of the package.
  for (const file of ['three.module.js', 'three.core.js']) copyFileSync(join(three, file), join(outDir, file));
  copyFileSync(join(here, 'node_modules/three/LICENSE'), join(outDir, 'three.LICENSE'));
  return outDir;
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  console.log(`studio page built into ${buildStudioAssets(process.argv[2] ? resolve(process.argv[2]) : undefined)}`);
}
