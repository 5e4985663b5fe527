// `tessera serve` as an HTTP server: requests in parallel (no two frames mixed), malformed, oversized
// and bad requests answered 4xx with a message and the server still up, path traversal refused,
// a render cancelled midway by a newer one, a rate bound, bad command lines refused with exit 2,
// and Ctrl-C stopping it cleanly with its folders removed.
// Usage: node server.test.mjs TESSERA_BINARY
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import net from 'node:net';
import { join } from 'node:path';
import { startServe, request, waitForRender } from './serve_process.mjs';

const tessera = process.argv[2];
assert.ok(tessera && existsSync(tessera), 'usage: node server.test.mjs TESSERA_BINARY');

// Sends raw bytes on a fresh connection; resolves with what came back before the server closed
// it (or 5 s passed).
function raw(base, bytes) {
  const { hostname, port } = new URL(base);
  return new Promise((resolve) => {
    let got = '';
    const socket = net.connect(Number(port), hostname, () => socket.write(bytes));
    socket.on('data', (d) => { got += d; });
    socket.on('error', () => resolve(got));
    socket.on('close', () => resolve(got));
    socket.setTimeout(5000, () => { socket.destroy(); resolve(got); });
  });
}

test('bad command lines exit 2 before serving, naming what is wrong', () => {
  for (const [args, says] of [
    [['--port', '70000'], '--port'],
    [['--dump', 'x'], '--dump'],
    [['-o', 'x.png'], '-o'],
    [['--width', '0'], '--width'],
    [['no-such-scene.json'], 'no-such-scene.json'],
  ]) {
    const r = spawnSync(tessera, ['serve', ...(args[0] === '--port' ? args : [...args, '--port', '0'])], { encoding: 'utf8', timeout: 60000 });
    assert.equal(r.status, 2, `serve ${args.join(' ')}: exit ${r.status}, stderr ${r.stderr}`);
    assert.match(r.stderr, new RegExp(says.replace(/[.]/g, '\\.')), `serve ${args.join(' ')} names ${says}`);
    assert.doesNotMatch(r.stdout, /http:/, 'no URL printed');
  }
});

test('the server', async (t) => {
  const serve = await startServe(tessera, ['default', '--technique', 'deferred', '--width', '160', '--height', '90', '--light-steps', '3']);
  const base = serve.url;
  const alive = async () => assert.equal((await request(base, '/api/status')).status, 200, 'the server still answers');

  await t.test('listens on the loopback address only', () => {
    assert.match(base, /^http:\/\/127\.0\.0\.1:/);
  });

  await t.test('serves the page and the first render', async () => {
    for (const name of ['index.html', 'app.js', 'style.css']) assert.equal((await request(base, `/${name}`)).status, 200, name);
    const r = await request(base, '/api/render/1');
    assert.equal(r.json.status, 'done');
    assert.equal(r.json.manifest.technique, 'deferred');
    assert.ok(r.json.files.includes('backbuffer.png'));
    assert.ok(r.json.passMs.lights > 0, 'pass times parsed from --stats');
    // --light-steps 3: the steps of lights 0..2 of the default scene's 4 (light 0, directional, has
    // no stencil steps but its shade step).
    assert.deepEqual(Object.keys(r.json.manifest.lightSteps).sort(), ['0', '1', '2']);
    // Every pass timed, names with spaces included ("copy depth"), from the run that dumped nothing:
    // the passes of one run fit in its frame time.
    const names = r.json.manifest.passes.map((p) => p.name);
    assert.ok(names.includes('copy depth'));
    assert.deepEqual(Object.keys(r.json.passMs).sort(), [...names].sort());
    const sum = Object.values(r.json.passMs).reduce((a, b) => a + b, 0);
    assert.ok(sum <= r.json.frameMs * 1.001 + 0.01, `passes ${sum} ms within the frame's ${r.json.frameMs} ms`);
  });

  await t.test('requests in parallel: each answer is its own, probes included', async () => {
    const pixels = [[10, 10], [80, 45], [150, 80], [40, 70]];
    const jobs = [];
    for (let i = 0; i < 40; ++i) {
      const path = ['/api/status', '/api/render/1', '/api/texels/1/backbuffer.png', '/index.html'][i % 4];
      jobs.push(request(base, path).then((r) => ({ path, r })));
    }
    for (const [x, y] of pixels) jobs.push(request(base, `/api/probe/1?x=${x}&y=${y}`).then((r) => ({ path: 'probe', x, y, r })));
    for (const { path, x, y, r } of await Promise.all(jobs)) {
      assert.equal(r.status, 200, `${path}: ${r.text.slice(0, 200)}`);
      if (path === 'probe') assert.deepEqual(r.json.pixel, [x, y], 'a probe answers the pixel it was asked');
      if (path === '/api/texels/1/backbuffer.png') {
        assert.equal(r.headers.get('x-width'), '160');
        assert.equal(r.text.length > 0, true);
      }
    }
  });

  await t.test('malformed requests get 4xx and the server stays up', async () => {
    assert.match(await raw(base, 'GARBAGE\r\n\r\n'), /^HTTP\/1\.1 400/);
    assert.match(await raw(base, `GET /${'a'.repeat(20000)} HTTP/1.1\r\nHost: x\r\n\r\n`), /^HTTP\/1\.1 (400|414)/);
    await raw(base, 'GET /api/status HTTP/1.1\r\nHost: x\r\nContent-Length: 10\r\n');  // cut off mid-headers
    await raw(base, Buffer.from([0, 255, 13, 10, 13, 10, 1, 2, 3]));
    await alive();
  });

  await t.test('oversized request bodies are refused (413)', async () => {
    const r = await request(base, '/api/render', { method: 'POST', body: 'x'.repeat(200 * 1024), headers: { 'Content-Type': 'application/json' } });
    assert.equal(r.status, 413);
    await alive();
  });

  await t.test('bad render requests: 400 with a message naming the key or value', async () => {
    const post = (body) => request(base, '/api/render', { method: 'POST', body, headers: { 'Content-Type': 'application/json' } });
    for (const [body, says] of [
      ['not json', /not JSON/],
      ['[1, 2]', /not a JSON object/],
      ['{"colour": 1}', /unknown key 'colour'/],
      ['{"width": 0}', /--width: '0'/],
      ['{"technique": "nope"}', /unknown technique 'nope'/],
      ['{"msaa": 3}', /--msaa/],
      ['{"options": 5}', /'options' must be an object/],
      ['{"width": -4}', /'width' must be/],
    ]) {
      const r = await post(body);
      assert.equal(r.status, 400, `${body}: ${r.status} ${r.text}`);
      assert.match(r.json.error, says, body);
    }
    for (const [path, status] of [
      ['/api/probe/1?x=abc&y=1', 400], ['/api/probe/1?x=5000&y=1', 400], ['/api/probe/1', 400],
      ['/api/render/999', 404], ['/api/files/999/backbuffer.png', 404], ['/api/texels/1/nothing.png', 404], ['/nothing.html', 404],
    ]) {
      const r = await request(base, path);
      assert.equal(r.status, status, `${path}: ${r.status} ${r.text}`);
      assert.ok(r.json && r.json.error, `${path} says why`);
    }
    await alive();
  });

  await t.test('path traversal is refused', async () => {
    const attempts = [
      '/api/files/1/../../../../../../etc/passwd', '/api/files/1/%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd',
      '/api/files/1/..%2f..%2f..%2f..%2fetc%2fpasswd', '/api/files/1//etc/passwd', '/api/texels/1/../../stdout.txt',
      '/api/files/1/../stdout.txt', '/../../../../etc/passwd', '/%2e%2e/%2e%2e/etc/passwd', '/..%2fsrc%2fcli%2fserve.cpp',
      '/api/files/1/after-gbuffer/../../../../../etc/passwd',
    ];
    for (const path of attempts) {
      const r = await raw(base, `GET ${path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`);
      assert.match(r, /^HTTP\/1\.1 (400|404)/, `${path}: ${r.slice(0, 80)}`);
      assert.doesNotMatch(r, /root:|#include/, `${path} leaked a file`);
    }
    await alive();
  });

  await t.test('a newer render cancels the one running; frames never mix', async () => {
    const post = (body) => request(base, '/api/render', { method: 'POST', body: JSON.stringify(body), headers: { 'Content-Type': 'application/json' } });
    const slow = await post({ width: 1280, height: 720 });
    assert.equal(slow.status, 202);
    const slowId = slow.json.id;
    for (;;) {  // until the slow one's child is running
      const s = (await request(base, '/api/status')).json;
      if (s.running === slowId) break;
      await new Promise((resolve) => setTimeout(resolve, 20));
    }
    const folder = join(serve.tmp, serve.workFolders()[0], `render-${slowId}`);
    assert.ok(existsSync(folder), 'the running render has its folder');
    const fast = await post({ width: 96, height: 54, technique: 'deferred-killzone' });
    const fastId = fast.json.id;
    assert.equal((await waitForRender(base, slowId)).status, 'cancelled');
    assert.equal((await waitForRender(base, fastId)).status, 'done');
    assert.ok(!existsSync(folder), 'the cancelled render left no folder');
    const cancelled = await request(base, `/api/files/${slowId}/backbuffer.png`);
    assert.equal(cancelled.status, 409, 'nothing is served from a cancelled render');
    const r = (await request(base, `/api/render/${fastId}`)).json;
    assert.equal(r.manifest.width, 96);
    assert.equal(r.manifest.technique, 'deferred-killzone');
    const texels = await request(base, `/api/texels/${fastId}/backbuffer.png`);
    assert.equal(texels.headers.get('x-width'), '96');
    assert.equal((await request(base, '/api/texels/1/backbuffer.png')).headers.get('x-width'), '160', 'the first render still reads as itself');
    // Renders of different sizes cannot be compared: 400 with tessera diff's message naming both.
    const diff = await request(base, `/api/diff/1/${fastId}`);
    assert.equal(diff.status, 400, diff.text);
    assert.match(diff.json.error, /160x90.*96x54|96x54.*160x90|size/);
    const same = await request(base, '/api/diff/1/1');
    assert.equal(same.status, 200, same.text);
    assert.equal(same.json.differing_pixels, 0);
    assert.equal((await request(base, same.json.heatmap)).status, 200, 'the heat map is served');
    assert.equal((await request(base, '/api/diffmap/1/77')).status, 404);
  });

  await t.test('cancel stops the running render', async () => {
    const r = await request(base, '/api/render', { method: 'POST', body: '{"width": 1280, "height": 720}', headers: { 'Content-Type': 'application/json' } });
    for (;;) {
      if ((await request(base, '/api/status')).json.running === r.json.id) break;
      await new Promise((resolve) => setTimeout(resolve, 20));
    }
    assert.equal((await request(base, '/api/cancel', { method: 'POST' })).json.cancelled, true);
    assert.equal((await waitForRender(base, r.json.id)).status, 'cancelled');
  });

  await t.test('a failing render is reported, not fatal', async () => {
    const r = await request(base, '/api/render', { method: 'POST', body: '{"options": {"noSuchOption": 1}}', headers: { 'Content-Type': 'application/json' } });
    const end = await waitForRender(base, r.json.id);
    assert.equal(end.status, 'failed');
    assert.match(end.message, /noSuchOption/);
    await alive();
  });

  await t.test('Ctrl-C stops it cleanly and removes its renders', async () => {
    assert.equal(serve.workFolders().length, 1);
    const end = await serve.stop();
    assert.equal(end.code, 0, `exit ${end.code} ${end.signal}: ${end.stderr}`);
    assert.match(end.stderr, /tessera serve: stopped/);
    assert.deepEqual(serve.workFolders(), [], 'its folder is gone');
  });
});

test('requests are rate-bounded (429 naming --max-rate), and served again after a pause', async () => {
  const serve = await startServe(tessera, ['builtin', '--width', '64', '--height', '64', '--max-rate', '20']);
  let limited = null;
  for (let round = 0; round < 20 && !limited; ++round) {  // --max-rate 20: 40 at once, then 20 a second
    const answers = await Promise.all(Array.from({ length: 20 }, () => request(serve.url, '/api/status')));
    limited = answers.find((a) => a.status === 429);
  }
  assert.ok(limited, 'some requests were refused with 429');
  assert.match(limited.json.error, /at most 20 per second \(--max-rate\)/);
  await new Promise((resolve) => setTimeout(resolve, 2500));
  assert.equal((await request(serve.url, '/api/status')).status, 200, 'served again after a pause');
  assert.equal((await serve.stop()).code, 0);
});
