// tailor studio in a real browser (Debian's chromium, headless, driven by puppeteer-core):
//  1. the page loads a shipped handle scene (scenes/cantilever_handle_reduced.json);
//  2. a scripted mouse drag of the handle changes the displayed E range, and the report the
//     server saves (report.json) carries the new target; the full-space check shows its error;
//  3. a frame series (scenes/swinging_beam.json's PVD) plays to its last frame, and a static
//     result (scenes/two_material_bar_inverse.json's) opens coloured by E, with its plots;
//  4. requests without the token, with a wrong token or from another origin are refused;
//  5. each other kind of output opens and draws (pixels on the canvas, the expected number of
//     bodies, rods and frame glyphs) with its plots: rods (a frame series and a static result),
//     tori and rigid bodies (their numbered files as a series), a periodic cell (E(d) polar
//     curves), an inverse run (convergence) and a damping study (decay envelopes).
// Screenshots go to --screenshots DIR. Exit 77 (ctest's skip) when chromium or the npm packages
// are missing. With --bench SCENE --json FILE it instead drags the handle of SCENE --drags N
// times and writes the release-to-redraw latencies (measured in the page) to FILE.
//
// Usage: node browser_test.mjs --tailor build/bin/tailor --source . [--screenshots DIR] [--only viewer]
//        node browser_test.mjs --tailor build/bin/tailor --source . --bench SCENE --json FILE [--drags N] [--assets DIR]
import { spawn, execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, mkdirSync, readFileSync, writeFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { buildStudioAssets } from '../build.mjs';

const SKIP = 77;
const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, a, i, all) => {
  if (a.startsWith('--')) pairs.push([a.slice(2), all[i + 1] && !all[i + 1].startsWith('--') ? all[i + 1] : true]);
  return pairs;
}, []));
const chromium = args.chromium || '/usr/bin/chromium';
if (!existsSync(chromium)) {
  console.log(`skipped: no browser at ${chromium} (Debian: chromium)`);
  process.exit(SKIP);
}
let puppeteer;
try {
  puppeteer = (await import('puppeteer-core')).default;
} catch {
  console.log('skipped: puppeteer-core is not installed (bash scripts/build-studio-web.sh runs npm ci)');
  process.exit(SKIP);
}
const tailor = resolve(args.tailor || 'build/bin/tailor');
const source = resolve(args.source || '.');
const work = mkdtempSync(join(tmpdir(), 'tailor-studio-browser-'));
let assets;
try {
  // --assets DIR: a page built elsewhere (e.g. an earlier commit's, to compare latencies).
  assets = args.assets ? resolve(args.assets) : buildStudioAssets(join(work, 'assets'));
} catch (error) {
  console.log(`skipped: ${error.message}`);
  rmSync(work, { recursive: true, force: true });
  process.exit(SKIP);
}
const servers = [];
let failures = 0;

function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) failures += 1;
}

// Starts `tailor studio target ...` and resolves with its URL once it prints it.
function startStudio(target, extra = []) {
  return new Promise((resolvePromise, reject) => {
    const child = spawn(tailor, ['studio', target, ...extra], { env: { ...process.env, TAILOR_STUDIO_ASSETS: assets } });
    servers.push(child);
    let out = '';
    const timer = setTimeout(() => reject(new Error(`no URL from tailor studio after 600 s:\n${out}`)), 600000);
    const read = (chunk) => {
      out += chunk;
      const m = out.match(/(http:\/\/127\.0\.0\.1:\d+\/[0-9a-f]+\/)/);
      if (m) {
        clearTimeout(timer);
        resolvePromise(m[1]);
      }
    };
    child.stdout.on('data', read);
    child.stderr.on('data', (chunk) => (out += chunk));
    child.on('exit', (code) => reject(new Error(`tailor studio exited (${code}):\n${out}`)));
  });
}

async function openPage(browser, url) {
  const page = await browser.newPage();
  await page.setViewport({ width: 1100, height: 640 });
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(url);
  await page.waitForFunction(() => window.studio && (window.studio.ready || window.studio.error), { timeout: 120000 });
  const error = await page.evaluate(() => window.studio.error);
  if (error) throw new Error(`the page failed: ${error}`);
  return page;
}

// Drags handle `h`'s sphere by (dx, dy) pixels with the mouse and waits for the redraw after release.
async function dragHandle(page, h, dx, dy) {
  const before = await page.evaluate(() => window.studio.design.releases.length);
  const at = await page.evaluate((h) => window.studio.viewer.toScreen(window.studio.design.targetPosition(h)), h);
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  for (let s = 1; s <= 5; ++s) await page.mouse.move(at.x + (dx * s) / 5, at.y + (dy * s) / 5);
  await page.mouse.up();
  await page.waitForFunction((n) => window.studio.design.releases.length > n, { timeout: 120000 }, before);
  const reply = await page.evaluate(() => window.studio.design.releases.at(-1));
  if (reply.type !== 'design') throw new Error(`the drag's design failed: ${reply.type}: ${reply.message}`);
  // The latency is pushed after the redraw that follows the reply.
  await page.waitForFunction((n) => window.studio.design.latencies.length >= n, { timeout: 120000 },
    await page.evaluate(() => window.studio.design.releases.filter((r) => r.type === 'design').length));
  return page.evaluate(() => window.studio.design.latencies.at(-1));
}

async function designTest(browser, shots) {
  const scene = join(source, 'scenes/cantilever_handle_reduced.json');
  const out = join(work, 'design');
  const url = await startStudio(scene, ['--out', out]);
  const page = await openPage(browser, url);
  check(await page.evaluate(() => window.studio.mode === 'design' && window.studio.design.designs === 1),
    'the page loads the shipped handle scene in design mode and designs for its target');
  const range0 = await page.evaluate(() => [...window.studio.design.range]);
  if (shots) await page.screenshot({ path: join(shots, 'studio_design_initial.png') });
  // The page designs for the scene's own target first; then drag the target down.
  const latency = await dragHandle(page, 0, 0, 12);
  const state = await page.evaluate(() => ({ range: [...window.studio.design.range], targets: window.studio.design.targets }));
  check(state.range[0] !== range0[0] || state.range[1] !== range0[1],
    `the drag changes the displayed E range: [${range0}] -> [${state.range}] (${latency.toFixed(1)} ms release to redraw)`);
  const check1 = await page.evaluate(() => window.studio.design.fullCheck());
  check(check1.type === 'full_check' && check1.converged, `full-space check: error ${check1.full_errors} (reduced ${check1.reduced_errors})`);
  if (shots) await page.screenshot({ path: join(shots, 'studio_design_dragged.png') });
  const saved = await page.evaluate(() => window.studio.design.save());
  check(saved.type === 'saved', 'save writes report.json and result.vtu');
  const report = JSON.parse(readFileSync(join(out, 'report.json'), 'utf8'));
  const saved_target = report.handles[0].target_displacement;
  check(saved_target.every((v, k) => Math.abs(v - state.targets[0][k]) < 1e-5 * (1 + Math.abs(v))),
    `the server's report carries the dragged target ${saved_target.map((v) => v.toFixed(4))}`);
  check(existsSync(join(out, 'result.vtu')), 'result.vtu written');
  await securityTest(url);
  await page.close();
}

async function securityTest(url) {
  const { origin, pathname } = new URL(url);
  const status = async (path, init) => (await fetch(origin + path, init)).status;
  check(await status('/') === 403, 'GET / without the token is refused (403)');
  check(await status('/api/message', { method: 'POST', body: '{"type":"hello"}' }) === 403, 'a message without the token is refused');
  check(await status('/0123456789abcdef0123456789abcdef/') === 403, 'a wrong token is refused');
  check(await status(pathname, { headers: { Origin: 'http://evil.example' } }) === 403, 'another origin is refused');
  check(await status(pathname + 'files/..%2F..%2Fetc%2Fpasswd') === 400, 'an encoded traversal is refused');
  check(await status(pathname) === 200, 'the page with its token is served');
}

async function framesTest(browser, shots) {
  const out = join(work, 'frames');
  execFileSync(tailor, ['simulate', join(source, 'scenes/swinging_beam.json'), '--out', out], { stdio: 'ignore' });
  const url = await startStudio(out);
  const page = await openPage(browser, url);
  const info = await page.evaluate(() => ({ mode: window.studio.mode, frames: window.studio.results.frames?.length ?? 0 }));
  check(info.mode === 'results' && info.frames > 1, `the viewer opens the frame series (${info.frames} frames)`);
  if (shots) await page.screenshot({ path: join(shots, 'studio_frames_first.png') });
  const shown = await page.evaluate(() => window.studio.results.framesShown);
  await page.click('#play');
  await page.waitForFunction((n) => window.studio.results.frame === n - 1 && !window.studio.results.playing,
    { timeout: 120000 }, info.frames);
  const after = await page.evaluate(() => window.studio.results.framesShown);
  check(after - shown >= info.frames - 1, `play shows every frame (${after - shown} drawn)`);
  if (shots) await page.screenshot({ path: join(shots, 'studio_frames_last.png') });
  // A static result with a field menu: the last frame's file on its own.
  const fields = await page.evaluate(() => [...document.getElementById('field').options].map((o) => o.value));
  check(fields.includes('cell:youngs_modulus') && fields.includes('point:displacement'), `field menu: ${fields.join(', ')}`);
  const range = await page.evaluate(() => window.studio.results.ranges.get('point:displacement'));
  check(range && range[1] > 0, `the frames are coloured by |displacement|, up to ${range?.[1]}`);
  await page.close();
}

async function staticResultTest(browser, shots) {
  const out = join(work, 'static');
  execFileSync(tailor, ['run', join(source, 'scenes/two_material_bar_inverse.json'), '--out', out, '--quiet'], { stdio: 'ignore' });
  const url = await startStudio(out);
  const page = await openPage(browser, url);
  const shown = await page.evaluate(() => ({
    file: document.getElementById('file').value,
    field: document.getElementById('field').value,
    bar: [document.getElementById('colorbar-min').textContent, document.getElementById('colorbar-max').textContent],
  }));
  check(shown.file === 'result.vtu' && shown.field === 'cell:youngs_modulus',
    `a static result opens coloured by Young's modulus (${shown.file}, ${shown.field}, colour bar ${shown.bar.join(' to ')})`);
  await page.waitForFunction(() => [...document.querySelectorAll('#plots img')].every((i) => i.complete), { timeout: 60000 });
  const plots = await page.evaluate(() => [...document.querySelectorAll('#plots img')].map((i) => [i.alt, i.naturalWidth]));
  check(plots.some(([name, width]) => name === 'convergence.png' && width > 0), `the folder's plots are shown: ${plots.map((p) => p[0]).join(', ')}`);
  if (shots) await page.screenshot({ path: join(shots, 'studio_result_static.png') });
  await page.close();
}

// Runs `tailor VERB SCENE --out DIR` (DIR under the work folder) and returns DIR.
function tailorOutput(verb, scene, name) {
  const out = join(work, name);
  execFileSync(tailor, [verb, scene, '--out', out], { stdio: 'ignore' });
  return out;
}

// Opens a folder in the viewer; returns the page and what it drew (bodies, rods, pixels, plots).
async function viewFolder(browser, out) {
  const url = await startStudio(out);
  const page = await openPage(browser, url);
  return { page, ...(await drawnState(page)) };
}

async function drawnState(page) {
  return page.evaluate(() => {
    const r = window.studio.results;
    return { drawn: r.drawn, frames: r.frames?.length ?? 0, pixels: window.studio.viewer.coloredPixels(),
      plots: r.plots.map((p) => p.kind), file: document.getElementById('file').value, field: document.getElementById('field').value,
      polarPoints: [...document.querySelectorAll('.report-plot.polar polygon')].map((p) => p.points.numberOfItems),
      convergencePoints: [...document.querySelectorAll('.report-plot.convergence polyline')].map((p) => p.points.numberOfItems) };
  });
}

async function playToEnd(page) {
  const n = await page.evaluate(() => window.studio.results.frames.length);
  await page.click('#play');
  await page.waitForFunction((n) => window.studio.results.frame === n - 1 && !window.studio.results.playing, { timeout: 120000 }, n);
  return drawnState(page);
}

async function outputKindsTest(browser, shots) {
  const shot = (page, name) => shots && page.screenshot({ path: join(shots, name) });
  // Rods, a frame series: one rod of 20 segments, its frame drawn at each segment (m1 and m2).
  let out = tailorOutput('simulate', join(source, 'scenes/rods/rod_swing.json'), 'rod_swing');
  let { page, ...state } = await viewFolder(browser, out);
  check(state.frames === 11 && state.drawn.rods === 1 && state.drawn.rodSegments === 20 && state.drawn.frameGlyphs === 40 && state.pixels > 500,
    `a rod's frame series draws as a tube with its frames: ${JSON.stringify(state.drawn)}, ${state.frames} frames, ${state.pixels} pixels, field ${state.field}`);
  state = await playToEnd(page);
  check(state.drawn.rods === 1 && state.pixels > 500, `the rod's frames play to the last (${state.pixels} pixels)`);
  check(state.plots.includes('energy'), `a dynamic run's energies are plotted: ${state.plots}`);
  await shot(page, 'studio_rods_swing.png');
  await page.close();
  // Rods, static: as many tubes as the report lists rods.
  out = tailorOutput('simulate', join(source, 'scenes/rods/rod_frame.json'), 'rod_frame');
  const rodCount = JSON.parse(readFileSync(join(out, 'report.json'), 'utf8')).scene.rods.length;
  ({ page, ...state } = await viewFolder(browser, out));
  check(state.drawn.rods === rodCount && state.drawn.rodSegments === 40 && state.pixels > 500,
    `a static rod result draws its ${rodCount} rods: ${JSON.stringify(state.drawn)}`);
  await page.close();
  // Tori: one file per link and output step, drawn together, every link in every frame.
  out = tailorOutput('simulate', join(source, 'scenes/contact/torus_chain.json'), 'torus_chain');
  ({ page, ...state } = await viewFolder(browser, out));
  check(state.file.startsWith('series:') && state.drawn.bodies === 5 && state.frames === 11 && state.pixels > 2000 && state.field === 'cell:#body',
    `a torus chain opens as a series of its 5 links, coloured by link: ${JSON.stringify(state.drawn)}, ${state.frames} frames, ${state.pixels} pixels`);
  state = await playToEnd(page);
  check(state.drawn.bodies === 5, 'the chain plays with every link in every frame');
  await shot(page, 'studio_tori.png');
  await page.close();
  // Rigid bodies: a box and the ground.
  out = tailorOutput('simulate', join(source, 'scenes/contact/box_drop.json'), 'box_drop');
  ({ page, ...state } = await viewFolder(browser, out));
  check(state.drawn.bodies === 2 && state.frames === 11 && state.pixels > 2000,
    `a rigid box and its ground open as one series: ${JSON.stringify(state.drawn)}, ${state.frames} frames`);
  await shot(page, 'studio_rigid.png');
  await page.close();
  // A periodic cell: its load cases and the E(d) polar curve of its report (one point per direction).
  out = tailorOutput('homogenize', join(source, 'scenes/homogenization/layered_square.json'), 'layered_square');
  const directions = JSON.parse(readFileSync(join(out, 'report.json'), 'utf8')).directional[0].angle_degrees.length;
  ({ page, ...state } = await viewFolder(browser, out));
  check(state.plots.includes('polar') && state.polarPoints[0] === directions && state.drawn.surfaceTriangles > 0 && state.pixels > 2000,
    `a periodic cell draws with its E(d) polar curve (${state.polarPoints} of ${directions} directions, ${state.drawn.surfaceTriangles} triangles)`);
  await shot(page, 'studio_periodic_cell.png');
  await page.close();
  // An inverse run: convergence, one point per iteration of its history.
  out = tailorOutput('run', join(source, 'scenes/two_material_bar_inverse.json'), 'inverse');
  const history = JSON.parse(readFileSync(join(out, 'report.json'), 'utf8')).history.length;
  ({ page, ...state } = await viewFolder(browser, out));
  check(state.plots.includes('convergence') && state.convergencePoints[0] === history,
    `an inverse run's convergence is plotted (${state.convergencePoints} points, ${history} iterations)`);
  await page.close();
  // A damping study (the shipped plate, fewer cells and steps): decay envelopes per mode.
  const plate = JSON.parse(readFileSync(join(source, 'problems/damping_design/damping_plate.json'), 'utf8'));
  Object.assign(plate.damping_design, { steps: 200 });
  plate.damping_design.plate.cells = [8, 2, 2];
  plate.damping_design.curve.steps = 200;
  const plateScene = join(work, 'damping_plate_small.json');
  writeFileSync(plateScene, JSON.stringify(plate));
  out = tailorOutput('run', plateScene, 'damping');
  const modes = JSON.parse(readFileSync(join(out, 'report.json'), 'utf8')).modes.length;
  ({ page, ...state } = await viewFolder(browser, out));
  const decayCurves = await page.evaluate(() => document.querySelectorAll('.report-plot.decay polyline').length);
  check(state.plots.includes('decay') && decayCurves === 3 * modes,
    `a damping study's decay envelopes are plotted (${decayCurves} curves for ${modes} modes: designed, target, plain)`);
  await shot(page, 'studio_damping.png');
  await page.close();
}

async function bench(browser) {
  const drags = Number(args.drags || 10);
  const url = await startStudio(resolve(args.bench), ['--out', join(work, 'bench')]);
  const page = await openPage(browser, url);
  const elements = await page.evaluate(() => window.studio.design.elements);
  const latencies = [], server = [], iterations = [], replies = [], errors = [];
  for (let i = 0; i < drags; ++i) {
    latencies.push(await dragHandle(page, 0, 0, i % 2 ? -25 : 30));
    server.push(await page.evaluate(() => 1e3 * window.studio.design.lastReply.seconds));
    iterations.push(await page.evaluate(() => window.studio.design.lastReply.iterations));
    replies.push(await page.evaluate(() => window.studio.design.releases.at(-1).reply_ms));
    errors.push(await page.evaluate(() => Math.max(...window.studio.design.lastReply.reduced_errors)));
  }
  // Where the time of each release went (ms; body: the request's round trip to the reply's last
  // byte, server: the design alone, so body - server is encoding, transfer and HTTP).
  const phases = await page.evaluate(() => window.studio.design.phases);
  const median = (v) => { const s = [...v].sort((a, b) => a - b); const n = s.length; return n % 2 ? s[(n - 1) / 2] : (s[n / 2 - 1] + s[n / 2]) / 2; };
  const phaseMedians = Object.fromEntries(Object.keys(phases[0] ?? {}).map((k) => [k, median(phases.map((p) => p[k]))]));
  const result = { bench: 'studio_latency', scene: args.bench, elements, drags, browser: await browser.version(),
    release_to_redraw_ms: latencies, median_release_to_redraw_ms: median(latencies),
    release_to_reply_ms: replies, median_release_to_reply_ms: median(replies),
    server_design_ms: server, median_server_design_ms: median(server), iterations,
    reduced_handle_errors: errors, median_reduced_handle_error: median(errors), phases, median_phases: phaseMedians,
    load_average: readFileSync('/proc/loadavg', 'utf8').trim(), goal_ms: 100 };
  writeFileSync(resolve(args.json || 'bench_studio_latency.json'), JSON.stringify(result, null, 2) + '\n');
  console.log(`${elements} tets, ${drags} drags: median release to redraw ${result.median_release_to_redraw_ms.toFixed(1)} ms, ` +
    `to the reply ${result.median_release_to_reply_ms.toFixed(1)} ms, server design ${result.median_server_design_ms.toFixed(1)} ms; goal 100 ms`);
  console.log(`median phases (ms): ${JSON.stringify(phaseMedians)}; load average ${result.load_average}`);
}

const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'],
});
try {
  if (args.bench) await bench(browser);
  else {
    const shots = args.screenshots ? resolve(args.screenshots) : null;
    if (shots) mkdirSync(shots, { recursive: true });
    // --only viewer: the result viewer's tests alone (no handle scene to precompute).
    if (args.only !== 'viewer') await designTest(browser, shots);
    await framesTest(browser, shots);
    await staticResultTest(browser, shots);
    await outputKindsTest(browser, shots);
  }
} catch (error) {
  console.log(`FAIL ${error.stack || error}`);
  failures += 1;
} finally {
  await browser.close();
  for (const s of servers) s.kill();
  rmSync(work, { recursive: true, force: true });
}
console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);
