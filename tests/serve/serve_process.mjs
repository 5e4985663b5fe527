// Starts `tessera serve` for a test: its own TMPDIR (so the test sees the render folders appear and
// go), any free port (--port 0), the URL read from its first stdout line; stop() sends SIGINT as
// Ctrl-C does and resolves with the exit code and stderr.
import { spawn } from 'node:child_process';
import { mkdtempSync, readdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export async function startServe(tessera, args) {
  const tmp = mkdtempSync(join(tmpdir(), 'tessera-serve-test-'));
  const proc = spawn(tessera, ['serve', ...args, '--port', '0'], { env: { ...process.env, TMPDIR: tmp }, stdio: ['ignore', 'pipe', 'pipe'] });
  let stdout = '', stderr = '';
  proc.stderr.on('data', (d) => { stderr += d; });
  const exited = new Promise((resolve) => proc.on('exit', (code, signal) => resolve({ code, signal })));
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`tessera serve printed no URL in 120 s; stderr: ${stderr}`)), 120000);
    proc.stdout.on('data', (d) => {
      stdout += d;
      const m = /http:\/\/[0-9.]+:[0-9]+\//.exec(stdout);
      if (m) { clearTimeout(timer); resolve(m[0]); }
    });
    exited.then(({ code }) => { clearTimeout(timer); reject(new Error(`tessera serve exited with ${code} before serving: ${stderr}`)); });
  });
  return {
    url, proc, tmp,
    stderr: () => stderr,
    // The server's own folders under its TMPDIR (tessera-serve-XXXXXX) and what they hold.
    workFolders: () => readdirSync(tmp).filter((n) => n.startsWith('tessera-serve-')),
    async stop() {
      proc.kill('SIGINT');
      const end = await exited;
      return { ...end, stderr };
    },
  };
}

// GET or POST against the server; the status and the body as text (and JSON where it parses).
export async function request(base, path, options = {}) {
  const response = await fetch(new URL(path, base), options);
  const text = await response.text();
  let json = null;
  try { json = JSON.parse(text); } catch { /* not JSON */ }
  return { status: response.status, text, json, headers: response.headers };
}

// Waits until render `id` has ended; its final summary from /api/status.
export async function waitForRender(base, id, timeoutMs = 240000) {
  const t0 = Date.now();
  for (;;) {
    const { json } = await request(base, '/api/status');
    const r = json.renders.find((x) => x.id === id);
    if (r && !['queued', 'running'].includes(r.status)) return r;
    if (Date.now() - t0 > timeoutMs) throw new Error(`render ${id} did not end in ${timeoutMs} ms`);
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
}
