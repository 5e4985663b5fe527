// `tessera serve`'s page in Debian's Chromium (puppeteer-core): it loads with no console error;
// clicking a lit pixel shows a history naming the draws and lights `tessera probe` names for that
// pixel; the deferred light slider changes the stencil picture; flipping an erratum's option and
// re-rendering changes the image, and the comparison shows tessera diff's count and the erratum.
// Screenshots are kept in ARTEFACT_DIR.
// Usage: node page.test.mjs TESSERA_BINARY ARTEFACT_DIR
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { existsSync, mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';
import { startServe, request } from './serve_process.mjs';

const [tessera, artefacts] = process.argv.slice(2);
assert.ok(tessera && existsSync(tessera) && artefacts, 'usage: node page.test.mjs TESSERA_BINARY ARTEFACT_DIR');
mkdirSync(artefacts, { recursive: true });
const chromium = '/usr/bin/chromium';
assert.ok(existsSync(chromium), 'Debian chromium is not installed (scripts/install-deps.sh installs it)');

const scene = ['default', '--technique', 'deferred', '--width', '320', '--height', '180'];
const pixel = [160, 100];  // lit by three of the default scene's four lights (the probe says which)

// What `tessera probe` says of the pixel: the draws that shaded it and the lights that added light.
function probeFacts() {
  const r = spawnSync(tessera, ['probe', scene[0], String(pixel[0]), String(pixel[1]), ...scene.slice(1), '--json'], { encoding: 'utf8', timeout: 120000 });
  assert.equal(r.status, 0, r.stderr);
  const history = JSON.parse(r.stdout);
  const draws = new Set(), lights = new Set();
  for (const e of history.events) {
    if (e.draw === undefined) continue;
    draws.add(String(e.draw));
    for (const t of e.lights || []) if (!t.none) lights.add(String(t.light));
  }
  return { draws, lights, names: history.lightNames };
}

// Chromium on a page of `serve`, every console error or warning, page error, failed request and
// error response collected into the returned `problems`; resolves once the page says it is ready.
async function openPage(serve) {
  const browser = await puppeteer.launch({ executablePath: chromium, headless: true, args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'] });
  const problems = [];
  const page = await browser.newPage();
  await page.setViewport({ width: 1500, height: 1100 });
  page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') problems.push(`console ${m.type()}: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => problems.push(`request failed: ${r.url()} ${r.failure() && r.failure().errorText}`));
  page.on('response', (r) => { if (r.status() >= 400) problems.push(`HTTP ${r.status()}: ${r.url()}`); });
  await page.goto(serve.url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
  return { browser, page, problems };
}

test('the page in Chromium', async (t) => {
  const expected = probeFacts();
  assert.ok(expected.draws.size >= 2 && expected.lights.size >= 2, 'the chosen pixel is lit (the test needs draws and lights to compare)');
  const serve = await startServe(tessera, scene);
  const { browser, page, problems } = await openPage(serve);
  try {
    await page.screenshot({ path: join(artefacts, 'serve-loaded.png'), fullPage: true });

    await t.test('the passes are listed with times and the buffers after each', async () => {
      const passes = await page.$$eval('#passList li', (lis) => lis.map((li) => li.dataset.pass));
      const manifest = (await request(serve.url, '/api/render/1')).json.manifest;
      assert.deepEqual(passes, manifest.passes.map((p) => p.name));
      await page.click('#passList li[data-pass="gbuffer"]');
      await page.waitForSelector('#bufferTabs button[data-buffer="gbuffer.normal"]');
      await page.click('#bufferTabs button[data-buffer="depth"]');
      await page.waitForSelector('#viewer[data-shown="gbuffer/depth"]');
      const ticks = await page.$eval('#colourBar', (c) => c.dataset.ticks);
      assert.equal(ticks, '5', 'the colour bar has labelled ticks');
    });

    await t.test('hovering a texel decodes it by format', async () => {
      const where = await page.$eval('#overlay', (c) => ({ ...c.dataset, rect: c.getBoundingClientRect().toJSON() }));
      const at = (x, y) => [where.rect.left + Number(where.panX) + (x + 0.5) * Number(where.zoom), where.rect.top + Number(where.panY) + (y + 0.5) * Number(where.zoom)];
      await page.mouse.move(...at(...pixel));
      const text = await page.$eval('#hover', (e) => e.textContent);
      assert.match(text, /\(160, 100\) depth D24_UNORM_S8_UINT/);
      assert.match(text, /D24 code \d+ of 16777215/);
      assert.match(text, /stencil \d+ = 0b[01]{8}/);
    });

    await t.test('clicking a lit pixel shows the draws and lights tessera probe names', async () => {
      await page.click('#passList li[data-pass="transparent"]');
      await page.waitForSelector('#viewer[data-shown="transparent/depth"]');
      const where = await page.$eval('#overlay', (c) => ({ ...c.dataset, rect: c.getBoundingClientRect().toJSON() }));
      await page.mouse.click(where.rect.left + Number(where.panX) + (pixel[0] + 0.5) * Number(where.zoom),
                             where.rect.top + Number(where.panY) + (pixel[1] + 0.5) * Number(where.zoom));
      await page.waitForSelector(`#historyBody[data-pixel="${pixel.join(',')}"]`, { timeout: 120000 });
      const shown = await page.evaluate(() => ({
        draws: [...document.querySelectorAll('#historyBody [data-draw]')].map((e) => e.dataset.draw),
        lights: [...document.querySelectorAll('#historyBody [data-light]:not(.nothing)')].map((e) => e.dataset.light),
        text: document.querySelector('#historyBody').textContent,
      }));
      assert.deepEqual(new Set(shown.draws), expected.draws, 'the same draws as tessera probe');
      assert.deepEqual(new Set(shown.lights), expected.lights, 'the same lights adding light as tessera probe');
      for (const light of expected.lights) assert.ok(shown.text.includes(`light ${light} '${expected.names[Number(light)]}'`), `light ${light} named`);
      await page.screenshot({ path: join(artefacts, 'serve-history.png'), fullPage: true });
    });

    await t.test('the deferred light slider changes the stencil picture', async () => {
      const stencilOf = () => page.$eval('#lightPictures', (box) => {
        const img = box.querySelector('img[data-step-file*="unmark"]');
        return { light: box.dataset.light, file: img && img.dataset.stepFile, loaded: img && img.complete && img.naturalWidth > 0 };
      });
      await page.waitForFunction(() => { const i = document.querySelector('#lightPictures img'); return i && i.complete && i.naturalWidth > 0; });
      const first = await stencilOf();
      assert.ok(first.file, `the default light ${first.light} shows its stencil after unmark`);
      const steps = (await request(serve.url, '/api/render/1')).json.manifest.lightSteps;
      const other = Object.keys(steps).find((l) => l !== first.light && steps[l].unmark);
      await page.$eval('#lightSlider', (s, v) => { s.value = v; s.dispatchEvent(new Event('input')); }, other);
      await page.waitForFunction((v) => document.querySelector('#lightPictures').dataset.light === v, {}, other);
      await page.waitForFunction(() => { const i = document.querySelector('#lightPictures img'); return i && i.complete && i.naturalWidth > 0; });
      const second = await stencilOf();
      assert.ok(second.file && second.file !== first.file, 'another light, another stencil file');
      const bytes = async (file) => (await fetch(new URL(`/api/files/1/${file.split('/').map(encodeURIComponent).join('/')}`, serve.url))).arrayBuffer();
      const [a, b] = await Promise.all([bytes(first.file), bytes(second.file)]);
      assert.ok(!Buffer.from(a).equals(Buffer.from(b)), 'the two stencil pictures differ');
      const changed = await page.$eval('#lightPictures canvas', (c) => Number(c.dataset.changed));
      assert.ok(changed > 0, 'the light changed some pixels');
    });

    await t.test('flipping an erratum and re-rendering changes the image', async () => {
      // reconstruct (ERRATA.md #3): the 3dgep demo reconstructs position from the pixel's corner.
      const corrected = await page.$eval('select[data-option="reconstruct"]', (s) => [...s.options].find((o) => o.textContent.includes('(corrected)')).value);
      await page.select('select[data-option="reconstruct"]', corrected);
      await page.click('#render');
      await page.waitForSelector('body[data-render="2"]', { timeout: 240000 });
      const r2 = (await request(serve.url, '/api/render/2')).json;
      assert.equal(r2.manifest.options.reconstruct, corrected);
      const image = async (id) => createHash('sha256').update(Buffer.from(await (await fetch(new URL(`/api/texels/${id}/backbuffer.png`, serve.url))).arrayBuffer())).digest('hex');
      assert.notEqual(await image(1), await image(2), 'the corrected reconstruction changes the image');
      // The comparison lists both renders; tessera diff's figures, heat map and erratum #3's row.
      await page.waitForFunction(() => document.querySelector('#compareA').options.length >= 2);
      await page.select('#compareA', '1');
      await page.select('#compareB', '2');
      await page.click('#compareRun');
      await page.waitForSelector('#compareBody[data-pair="1-2"]', { timeout: 120000 });
      const shown = await page.$eval('#compareBody', (b) => ({
        differing: Number(b.dataset.differing), errata: [...b.querySelectorAll('[data-erratum]')].map((e) => e.dataset.erratum),
        text: b.textContent,
      }));
      for (const id of [1, 2])
        writeFileSync(join(artefacts, `render-${id}.png`), Buffer.from(await (await fetch(new URL(`/api/files/${id}/backbuffer.png`, serve.url))).arrayBuffer()));
      const direct = spawnSync(tessera, ['diff', '--json', join(artefacts, 'render-1.png'), join(artefacts, 'render-2.png')], { encoding: 'utf8' });
      assert.equal(direct.status, 0, direct.stderr);
      assert.ok(shown.differing > 0, 'the diff counts differing pixels');
      assert.equal(shown.differing, JSON.parse(direct.stdout).differing_pixels, 'as tessera diff counts them');
      assert.deepEqual(shown.errata, ['3'], 'the erratum the two renders differ in');
      assert.match(shown.text, /int2\(SV_Position\.xy\)/, "ERRATA.md #3's text");
      await page.waitForFunction(() => { const i = document.querySelector('#diffHeatmap'); return i && i.complete && i.naturalWidth > 0; });
      await page.screenshot({ path: join(artefacts, 'serve-corrected.png'), fullPage: true });
    });

    await t.test('no console error, failed request or error response', () => {
      assert.deepEqual(problems, []);
    });
  } finally {
    await browser.close();
    const end = await serve.stop();
    assert.equal(end.code, 0, end.stderr);
  }
});

test('tiles: light counts over the image and a tile\'s list and 2.5D mask (forward-plus-amd)', async () => {
  const args = ['default', '--technique', 'forward-plus-amd', '--width', '160', '--height', '96'];
  const serve = await startServe(tessera, args);
  const { browser, page, problems } = await openPage(serve);
  try {
    const manifest = (await request(serve.url, '/api/render/1')).json.manifest;
    const grid = manifest.buffers.find((b) => b.name === 'lightgrid.opaque');
    assert.ok(grid, 'forward-plus-amd writes lightgrid.opaque');
    // The largest count of the grid, from its raw texels: (offset, count) uint32 pairs.
    const raw = await fetch(new URL(`/api/texels/1/${grid.file}`, serve.url));
    const counts = new Uint32Array(await raw.arrayBuffer()).filter((_, i) => i % 2 === 1);
    const max = Math.max(...counts);
    await page.select('#tileGrid', 'lightgrid.opaque');
    await page.click('#tiles');
    await page.waitForFunction(() => !document.querySelector('#tileBar').hidden);
    assert.equal(await page.$eval('#tileBar', (c) => c.dataset.max), String(max), 'the scale runs to the largest count');
    // A pixel's tile: the history's tile block names the probe's tile and the mask's texel.
    const pixel = [80, 50];
    const r = spawnSync(tessera, ['probe', args[0], ...pixel.map(String), ...args.slice(1), '--json'], { encoding: 'utf8', timeout: 120000 });
    const tile = JSON.parse(r.stdout).tile;
    const where = await page.$eval('#overlay', (c) => ({ ...c.dataset, rect: c.getBoundingClientRect().toJSON() }));
    await page.mouse.click(where.rect.left + Number(where.panX) + (pixel[0] + 0.5) * Number(where.zoom),
                           where.rect.top + Number(where.panY) + (pixel[1] + 0.5) * Number(where.zoom));
    await page.waitForSelector('#historyBody [data-tile] [data-mask]', { timeout: 120000 });
    const shown = await page.$eval('#historyBody [data-tile]', (d) => ({ tile: d.dataset.tile, mask: d.querySelector('[data-mask]').dataset.mask, text: d.textContent }));
    assert.equal(shown.tile, tile.tile.join(','));
    for (const light of tile.lights) assert.match(shown.text, new RegExp(`light ${light}\\b`));
    const maskBuffer = manifest.buffers.find((b) => b.name.endsWith('depthMask'));
    const masks = new Uint32Array(await (await fetch(new URL(`/api/texels/1/${maskBuffer.file}`, serve.url))).arrayBuffer());
    assert.equal(shown.mask, String(masks[tile.tile[1] * maskBuffer.width + tile.tile[0]]), "the tile's 2.5D mask");
    await page.screenshot({ path: join(artefacts, 'serve-tiles.png'), fullPage: true });
    assert.deepEqual(problems, []);
  } finally {
    await browser.close();
    assert.equal((await serve.stop()).code, 0);
  }
});

test("Killzone 2's light steps: each light's query count and threshold, shaded exactly when the count exceeds it", async () => {
  const serve = await startServe(tessera, ['default', '--technique', 'deferred-killzone', '--width', '160', '--height', '90']);
  const { browser, page, problems } = await openPage(serve);
  try {
    const steps = (await request(serve.url, '/api/render/1')).json.manifest.lightSteps;
    const decisions = [];
    for (const light of Object.keys(steps).filter((l) => steps[l].count)) {
      await page.$eval('#lightSlider', (s, v) => { s.value = v; s.dispatchEvent(new Event('input')); }, light);
      await page.waitForFunction((v) => document.querySelector('#lightPictures').dataset.light === v && document.querySelector('#killzoneCount'), {}, light);
      const shown = await page.$eval('#killzoneCount', (p) => ({ count: Number(p.dataset.count), threshold: Number(p.dataset.threshold), text: p.textContent }));
      assert.equal(shown.threshold, 0, 'the faithful threshold');
      // The technique shaded the light (a shade step in the dump) exactly when count > threshold.
      assert.equal(Boolean(steps[light].shade), shown.count > shown.threshold, `light ${light}: ${shown.text}`);
      assert.match(shown.text, shown.count > shown.threshold ? /shaded/ : /skipped/);
      decisions.push(shown.count > shown.threshold);
    }
    // The default scene has both kinds: lights whose volume holds the eye mark nothing (skipped).
    assert.ok(decisions.includes(true) && decisions.includes(false), `shaded and skipped lights: ${decisions}`);
    assert.deepEqual(problems, []);
  } finally {
    await browser.close();
    assert.equal((await serve.stop()).code, 0);
  }
});

test("Forward+'s tile planes drawn along the clicked pixel's tile edges", async () => {
  // 160x96, 16 px tiles: pixel (80, 50) is in tile (5, 3), whose edges are x = 80, 96 and y = 48, 64.
  // The 3dgep planes (left, right, top, bottom) pass through the eye and those edges, so each cuts
  // the image along one edge: within half a pixel (binary32 planes, the page's double arithmetic).
  const serve = await startServe(tessera, ['default', '--technique', 'forward-plus', '--width', '160', '--height', '96']);
  const { browser, page, problems } = await openPage(serve);
  try {
    const where = await page.$eval('#overlay', (c) => ({ ...c.dataset, rect: c.getBoundingClientRect().toJSON() }));
    await page.mouse.click(where.rect.left + Number(where.panX) + 80.5 * Number(where.zoom), where.rect.top + Number(where.panY) + 50.5 * Number(where.zoom));
    await page.waitForSelector('#historyBody[data-pixel="80,50"]', { timeout: 120000 });
    const lines = JSON.parse(await page.$eval('#overlay', (c) => c.dataset.planeLines));
    assert.equal(lines.length, 4);
    const near = (a, b) => Math.abs(a - b) <= 0.5;
    const [left, right, top, bottom] = lines;
    for (const [line, x] of [[left, 80], [right, 96]]) assert.ok(near(line[0], x) && near(line[2], x), `vertical line ${line} at x = ${x}`);
    for (const [line, y] of [[top, 48], [bottom, 64]]) assert.ok(near(line[1], y) && near(line[3], y), `horizontal line ${line} at y = ${y}`);
    assert.deepEqual(problems, []);
  } finally {
    await browser.close();
    assert.equal((await serve.stop()).code, 0);
  }
});
