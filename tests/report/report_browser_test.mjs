// Acceptance test of issue 8: the report.html of a built-in example run, opened in headless
// Chromium from file:// with every network request refused, must load without console errors,
// draw a 3D view that is not blank, redraw the print paths when the layer slider moves, and leave
// a screenshot under the build tree.
// Usage: node report_browser_test.mjs --flatmorph BIN --out DIR [--chromium PATH]
import { execFileSync } from 'node:child_process';
import { createRequire } from 'node:module';
import { existsSync, mkdirSync, rmSync, statSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const flatmorph = args.flatmorph;
const out = resolve(args.out || 'report-browser-test');
const chromiumPath = args.chromium || '/usr/bin/chromium';

function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exit(1);
}
if (!flatmorph || !existsSync(flatmorph)) fail(`no flatmorph binary at '${flatmorph}' (--flatmorph)`);
if (!existsSync(chromiumPath)) fail(`no Chromium at '${chromiumPath}': run scripts/setup (it installs Debian's chromium)`);
const require = createRequire(join(here, '../../web/package.json'));
let chromium;
try {
  ({ chromium } = require('playwright-core'));
} catch (e) {
  fail('playwright-core is missing from web/node_modules: run scripts/setup (npm ci in web/)');
}

// 1. A small run of a built-in example: plate, theta1 and theta2, predicted shape, G-code.
const run = join(out, 'saddle');
rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
const cli = (...a) => execFileSync(flatmorph, ['--quiet', ...a], { stdio: ['ignore', 'ignore', 'inherit'] });
cli('design', '--example', 'saddle', '--width', '80', '--faces', '1000', '--layers', '6',
  '--printer', 'creality-cr10s-pro', '-o', run);
if (!existsSync(join(run, 'plate.gcode'))) {
  cli('toolpaths', join(run, 'flat.ply'), '--printer', 'creality-cr10s-pro', '--layers', '6', '-o', run);
}
cli('report', run);
const report = join(run, 'report.html');
console.log(`report: ${report} (${(statSync(report).size / 1e6).toFixed(2)} MB)`);

// 2. Headless Chromium, offline: only file:// may load.
const browser = await chromium.launch({
  executablePath: chromiumPath,
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const problems = [];
try {
  const context = await browser.newContext({ offline: true, viewport: { width: 1280, height: 1100 } });
  await context.route('**/*', (route) => {
    const url = route.request().url();
    if (url.startsWith('file:') || url.startsWith('data:')) return route.continue();
    problems.push(`network request to ${url}`);
    return route.abort();
  });
  const page = await context.newPage();
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  await page.goto(pathToFileURL(report).href, { waitUntil: 'load' });
  await page.waitForFunction(() => window.flatmorphViewer && window.flatmorphViewer.ready, null, { timeout: 60000 });

  // 3. The 3D canvas is not blank: variance of its grey levels.
  const stats = await page.evaluate(() => {
    const gl = document.getElementById('view3d-canvas');
    if (!gl) return null;
    const c = document.createElement('canvas');
    c.width = gl.width;
    c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    let sum = 0, sum2 = 0;
    const n = d.length / 4;
    for (let i = 0; i < d.length; i += 4) {
      const y = 0.299 * d[i] + 0.587 * d[i + 1] + 0.114 * d[i + 2];
      sum += y;
      sum2 += y * y;
    }
    const mean = sum / n;
    return { width: c.width, height: c.height, variance: sum2 / n - mean * mean };
  });
  if (!stats) problems.push('no 3D canvas (#view3d-canvas): WebGL unavailable?');
  else {
    console.log(`3D canvas ${stats.width} x ${stats.height}, grey-level variance ${stats.variance.toFixed(1)}`);
    if (!(stats.variance > 50)) problems.push(`the 3D canvas looks blank (variance ${stats.variance.toFixed(2)} <= 50)`);
  }

  // 4. Moving the layer slider (with the keyboard, as a user would) redraws the paths.
  const layerCount = await page.evaluate(() => window.flatmorphViewer.layerCount);
  if (layerCount < 2) problems.push(`the report shows ${layerCount} layer(s), expected 6`);
  const snapshot = () => page.evaluate(() => document.getElementById('layer-canvas').toDataURL());
  const first = await snapshot();
  const slider = page.locator('#layer-slider');
  await slider.focus();
  await page.keyboard.press('End');
  const last = await snapshot();
  const shown = await page.evaluate(() => window.flatmorphViewer.layer);
  if (shown !== layerCount) problems.push(`after End the viewer shows layer ${shown}, not ${layerCount}`);
  if (first === last) problems.push('the drawn paths did not change when the layer slider moved');
  await page.keyboard.press('ArrowLeft');
  if ((await snapshot()) === last) problems.push('the drawn paths did not change on ArrowLeft');
  await page.click('input[name=plate-field][value=theta2]');

  // 5. A screenshot for people.
  const shot = join(out, 'report.png');
  await page.screenshot({ path: shot, fullPage: true });
  console.log(`screenshot: ${shot}`);
} finally {
  await browser.close();
}
if (problems.length) fail(problems.join('\n      '));
console.log('PASS');
