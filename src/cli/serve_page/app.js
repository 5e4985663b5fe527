// tessera serve's page: loads a render's manifest (/api/render/ID), lists its passes, shows any
// buffer after any pass from its raw texels (/api/texels/...) with zoom, pan, channel and range
// controls and the hovered texel decoded by format, a clicked pixel's history (/api/probe/ID), the
// deferred light steps, and sends re-render requests (/api/render) built from the option catalogue.
'use strict';

const $ = (id) => document.getElementById(id);
const state = {
  techniques: [], render: null, pass: null, buffer: null, view: null, zoom: 1, panX: 0, panY: 0,
  channels: [true, true, true, false], lo: 0, hi: 1, picked: null, probe: null,
};

async function api(path, options) {
  const response = await fetch(path, options);
  const type = response.headers.get('Content-Type') || '';
  const body = type.startsWith('application/json') ? await response.json() : null;
  if (!response.ok) throw new Error((body && body.error) || `${path}: HTTP ${response.status}`);
  return body;
}

function setStatus(text, failed = false) {
  $('status').textContent = text;
  $('status').className = failed ? 'failed' : '';
}

// A number as people read it: up to 6 significant digits (the probe's text uses the same).
function num(v) {
  if (typeof v !== 'number') return String(v);
  if (Number.isInteger(v)) return String(v);
  return String(Number(v.toPrecision(6)));
}
const vec = (a) => (Array.isArray(a) ? `[${a.map(num).join(', ')}]` : num(a));
const el = (tag, attrs = {}, text = '') => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text) e.textContent = text;
  return e;
};
const filePath = (folder, file) => (folder ? `${folder}/${file}` : file);
const urlPath = (path) => path.split('/').map(encodeURIComponent).join('/');
const technique = () => state.techniques.find((t) => t.id === state.render.manifest.technique) || { passes: {}, options: [] };

// ---- render controls --------------------------------------------------------------------------

function fillControls() {
  const m = state.render.manifest;
  const select = $('technique');
  select.replaceChildren(...state.techniques.filter((t) => t.ready).map((t) => el('option', { value: t.id, title: t.summary }, t.id)));
  select.value = m.technique;
  $('width').value = m.width;
  $('height').value = m.height;
  $('msaa').value = String(m.msaa || 1);
  $('precision').value = m.precision || 'exact';
  fillOptions(m.technique, m.options || {});
}

// An option's faithful default as one of its values (the catalogue may say more: "d3d (shading 3dgep: demo-gl)").
const faithfulValue = (o) => (o.values.includes(o.faithful) ? o.faithful : o.values.find((v) => o.faithful.startsWith(v)) || o.faithful);

// One select per option of the technique's catalogue, faithful and corrected values marked.
function fillOptions(id, current) {
  const t = state.techniques.find((x) => x.id === id);
  const box = $('options');
  box.replaceChildren();
  for (const o of (t ? t.options : [])) {
    if (!o.values || o.values.length === 0) continue;
    const label = el('label', { title: o.meaning + (o.erratum ? ` (ERRATA.md #${o.erratum})` : '') }, o.key + (o.erratum ? ` #${o.erratum} ` : ' '));
    const s = el('select', { 'data-option': o.key });
    for (const v of o.values) {
      const mark = v === faithfulValue(o) ? ' (faithful)' : v === o.corrected ? ' (corrected)' : '';
      s.append(el('option', { value: v }, v + mark));
    }
    const value = current[o.key] !== undefined ? String(current[o.key]) : faithfulValue(o);
    s.value = o.values.includes(value) ? value : faithfulValue(o);
    label.append(s);
    box.append(label);
  }
}

// The option keys the server's command line sets (--option KEY=VALUE in its first render's arguments).
function commandLineOptions() {
  const keys = new Set();
  const args = state.firstArgs || [];
  for (let i = 0; i + 1 < args.length; ++i) if (args[i] === '--option') keys.add(args[i + 1].split('=')[0]);
  return keys;
}

async function submitRender(event) {
  event.preventDefault();
  const options = {};
  for (const s of document.querySelectorAll('[data-option]')) {
    const o = (state.techniques.find((t) => t.id === $('technique').value) || { options: [] }).options.find((x) => x.key === s.dataset.option);
    // The default is left out (requests and their labels stay short), unless the server's own
    // command line set the option otherwise.
    if (o && s.value === faithfulValue(o) && !commandLineOptions().has(o.key)) continue;
    options[s.dataset.option] = o && (o.kind === 'bool' || o.kind === 'integer') ? JSON.parse(s.value) : s.value;
  }
  const body = {
    technique: $('technique').value, width: Number($('width').value), height: Number($('height').value),
    msaa: Number($('msaa').value), precision: $('precision').value, options,
  };
  if ($('lights').value !== '') body.lights = Number($('lights').value);
  try {
    const { id } = await api('/api/render', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
    await waitFor(id);
  } catch (e) {
    setStatus(e.message, true);
  }
}

// Polls the server until render `id` ends; shows the child's progress line meanwhile.
async function waitFor(id) {
  for (;;) {
    const s = await api('/api/status');
    const r = s.renders.find((x) => x.id === id);
    if (!r) return setStatus(`render ${id} is unknown`, true);
    if (r.status === 'done') return loadRender(id);
    if (r.status === 'failed') return setStatus(`render ${id} failed: ${r.message || ''}`, true);
    if (r.status === 'cancelled') return setStatus(`render ${id} was cancelled`);
    setStatus(`render ${id} ${r.status}${s.progress ? ': ' + s.progress : ''}`);
    await new Promise((resolve) => setTimeout(resolve, 200));
  }
}

// ---- passes and buffers -----------------------------------------------------------------------

async function loadRender(id) {
  state.render = await api(`/api/render/${id}`);
  const m = state.render.manifest;
  $('scene').textContent = `${m.scene} · ${m.technique} · ${m.width}x${m.height}`;
  setStatus(`render ${id}: frame ${num(state.render.frameMs)} ms (the faster of two runs, the other writing every buffer), ${num(state.render.wallMs)} ms in all`);
  document.body.dataset.render = String(id);
  fillControls();
  const list = $('passList');
  list.replaceChildren();
  const captions = technique().passes || {};
  for (const p of m.passes) {
    const li = el('li', { 'data-pass': p.name, title: captions[p.name] || '' });
    li.append(el('span', { class: 'ms' }, state.render.passMs[p.name] !== undefined ? `${num(state.render.passMs[p.name])} ms` : ''));
    li.append(el('span', {}, p.name));
    li.append(el('div', { class: 'rw' }, `reads ${p.reads.join(', ') || 'nothing'}; writes ${p.writes.join(', ') || 'nothing'}`));
    li.addEventListener('click', () => selectPass(p.name));
    list.append(li);
  }
  $('frameTime').textContent = `frame ${num(state.render.frameMs)} ms`;
  const last = m.passes.length ? m.passes[m.passes.length - 1].name : null;
  state.picked = null;
  state.probeLights = [];
  $('historyBody').replaceChildren();
  await selectPass(last);
  setupLightSteps();
  await setupTiles();
  await fillCompareLists();
}

// The buffers as they stood after `pass` (the dump's after-<pass>/ folder).
async function selectPass(pass) {
  state.pass = pass;
  for (const li of document.querySelectorAll('#passList li')) li.classList.toggle('selected', li.dataset.pass === pass);
  const after = state.render.manifest.after[pass];
  const tabs = $('bufferTabs');
  tabs.replaceChildren();
  const entries = [];
  for (const b of after.buffers) {
    entries.push({ label: b.name, buffer: b, file: filePath(after.folder, b.file), stencil: b.stencilFile ? filePath(after.folder, b.stencilFile) : null });
    if (b.stencilFile) entries.push({ label: `${b.name} stencil`, buffer: b, file: filePath(after.folder, b.stencilFile), isStencil: true });
  }
  for (const e of entries) {
    const button = el('button', { type: 'button', role: 'tab', 'data-buffer': e.label }, e.label);
    button.addEventListener('click', () => selectBuffer(e));
    tabs.append(button);
  }
  const keep = state.buffer && entries.find((e) => e.label === state.buffer.label);
  const first = keep || entries.find((e) => e.label === 'backbuffer') || entries[0];
  if (first) await selectBuffer(first);
}

async function fetchTexels(path) {
  const response = await fetch(`/api/texels/${state.render.id}/${urlPath(path)}`);
  if (!response.ok) throw new Error(`${path}: ${(await response.json()).error}`);
  const bytes = await response.arrayBuffer();
  const type = response.headers.get('X-Type');
  const data = type === 'float32' ? new Float32Array(bytes) : type === 'uint32' ? new Uint32Array(bytes) : new Uint8Array(bytes);
  return { width: Number(response.headers.get('X-Width')), height: Number(response.headers.get('X-Height')),
           channels: Number(response.headers.get('X-Channels')), type, data };
}

const isDepthFormat = (format) => /^D(16|24|32)/.test(format);
const isUint = (view) => view.type === 'uint32' || view.entry.isStencil;

async function selectBuffer(entry) {
  state.buffer = entry;
  for (const b of document.querySelectorAll('#bufferTabs button')) b.classList.toggle('selected', b.dataset.buffer === entry.label);
  try {
    const texels = await fetchTexels(entry.file);
    const stencil = entry.stencil ? await fetchTexels(entry.stencil) : null;
    const sizeChanged = !state.view || state.view.texels.width !== texels.width || state.view.texels.height !== texels.height;
    if (sizeChanged) state.fitted = false;
    state.view = { entry, texels, stencil };
  } catch (e) {
    setStatus(e.message, true);
    return;
  }
  const c = state.view.texels.channels;
  state.channels = [true, c > 1, c > 2, c > 3 && (state.view.texels.type !== 'uint8' || entry.buffer.name.startsWith('gbuffer.'))];
  if (c === 4 && state.view.texels.type === 'uint8' && !entry.buffer.name.startsWith('gbuffer.')) state.channels[3] = false;
  fillChannels();
  $('srgb').checked = false;
  fitRange();
  $('bufferRule').textContent = entry.isStencil ? 'stencil: the 8-bit stencil code of each pixel' : entry.buffer.decode || '';
  if (!state.fitted) fitView();
  draw();
  drawOverlay();
  $('viewer').dataset.shown = `${state.pass}/${entry.label}`;  // drawn and laid out (tests wait for it)
}

function fillChannels() {
  const box = $('channels');
  box.replaceChildren();
  const names = 'RGBA';
  for (let i = 0; i < state.view.texels.channels; ++i) {
    const label = el('label', {}, names[i] + ' ');
    const box2 = el('input', { type: 'checkbox', 'data-channel': String(i) });
    box2.checked = state.channels[i];
    box2.addEventListener('change', () => { state.channels[i] = box2.checked; fitRange(); draw(); });
    label.prepend(box2);
    box.append(label);
  }
}

// The value range of the enabled channels (a depth buffer's cleared 1.0 left out, as --dump's view does).
function fitRange() {
  const { texels, entry } = state.view;
  let lo = Infinity, hi = -Infinity;
  const depth = isDepthFormat(entry.buffer.format) && !entry.isStencil;
  for (let i = 0; i < texels.data.length; i += texels.channels)
    for (let c = 0; c < texels.channels; ++c) {
      if (!state.channels[c]) continue;
      let v = texels.data[i + c];
      if (texels.type === 'uint8' && !entry.isStencil) v /= 255;
      if (!Number.isFinite(v) || (depth && v >= 1)) continue;
      lo = Math.min(lo, v);
      hi = Math.max(hi, v);
    }
  if (!Number.isFinite(lo)) { lo = 0; hi = 1; }
  if (texels.type === 'uint8' && !entry.isStencil && !depth) { lo = Math.min(lo, 0); hi = Math.max(hi, 1); }
  if (isUint(state.view)) lo = Math.min(lo, 0);
  if (hi <= lo) hi = lo + 1;
  state.lo = lo;
  state.hi = hi;
  $('rangeLo').value = num(lo);
  $('rangeHi').value = num(hi);
}

// The heat ramp of --dump's integer views: black, blue, green, yellow, white.
function heat(t) {
  const stops = [[0, 0, 0], [0, 0, 255], [0, 200, 0], [255, 230, 0], [255, 255, 255]];
  const x = Math.max(0, Math.min(1, t)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const f = x - i;
  return stops[i].map((a, k) => Math.round(a + (stops[i + 1][k] - a) * f));
}
const srgbEncode = (v) => (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055);

// A texel's display colour under the channel toggles, range and encoding.
function colourOf(values) {
  const t = (v) => (v - state.lo) / (state.hi - state.lo);
  const on = state.channels.map((c, i) => c && i < values.length);
  const count = on.filter(Boolean).length;
  if (isUint(state.view) && count === 1) return heat(t(values[on.indexOf(true)]));
  const enc = (v) => Math.round(255 * Math.max(0, Math.min(1, $('srgb').checked ? srgbEncode(Math.max(0, Math.min(1, t(v)))) : t(v))));
  if (count === 1) { const g = enc(values[on.indexOf(true)]); return [g, g, g]; }
  return [0, 1, 2].map((c) => (on[c] ? enc(values[c]) : 0));
}

function texelValues(texels, x, y) {
  const i = (y * texels.width + x) * texels.channels;
  const out = [];
  for (let c = 0; c < texels.channels; ++c) {
    const v = texels.data[i + c];
    out.push(texels.type === 'uint8' && !(state.view.entry.isStencil && texels === state.view.texels) ? v / 255 : v);
  }
  return out;
}

function draw() {
  const { texels } = state.view;
  const off = document.createElement('canvas');
  off.width = texels.width;
  off.height = texels.height;
  const ctx = off.getContext('2d');
  const image = ctx.createImageData(texels.width, texels.height);
  for (let y = 0; y < texels.height; ++y)
    for (let x = 0; x < texels.width; ++x) {
      const [r, g, b] = colourOf(texelValues(texels, x, y));
      const o = (y * texels.width + x) * 4;
      image.data[o] = r; image.data[o + 1] = g; image.data[o + 2] = b; image.data[o + 3] = 255;
    }
  ctx.putImageData(image, 0, 0);
  state.offscreen = off;
  paint();
  drawColourBar();
}

// The offscreen picture scaled by the zoom with nearest texels, at the pan offset.
function paint() {
  const box = $('canvasBox');
  for (const c of [$('image'), $('overlay')]) { c.width = box.clientWidth; c.height = box.clientHeight; }
  const ctx = $('image').getContext('2d');
  ctx.imageSmoothingEnabled = false;
  ctx.clearRect(0, 0, ctx.canvas.width, ctx.canvas.height);
  if (state.offscreen)
    ctx.drawImage(state.offscreen, state.panX, state.panY, state.offscreen.width * state.zoom, state.offscreen.height * state.zoom);
  $('zoomText').textContent = `zoom ${num(state.zoom)}x`;
  // Where texel (0, 0) lands and how big a texel is, for tools that click a given pixel.
  Object.assign($('overlay').dataset, { zoom: String(state.zoom), panX: String(state.panX), panY: String(state.panY) });
  drawOverlay();
}

function fitView() {
  const box = $('canvasBox');
  const { width, height } = state.view.texels;
  state.zoom = Math.max(0.125, Math.min(box.clientWidth / width, box.clientHeight / height));
  state.panX = (box.clientWidth - width * state.zoom) / 2;
  state.panY = (box.clientHeight - height * state.zoom) / 2;
  state.fitted = true;
}

// The colour bar: the mapping from lo to hi with five labelled ticks.
function drawColourBar() {
  const canvas = $('colourBar');
  canvas.width = canvas.clientWidth || 600;
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const n = state.view.texels.channels;
  for (let x = 0; x < canvas.width; ++x) {
    const v = state.lo + (state.hi - state.lo) * (x / (canvas.width - 1));
    const values = new Array(n).fill(v);
    const [r, g, b] = colourOf(values);
    ctx.fillStyle = `rgb(${r},${g},${b})`;
    ctx.fillRect(x, 0, 1, 16);
  }
  ctx.fillStyle = '#d8dbe0';
  ctx.font = '11px system-ui';
  for (let k = 0; k <= 4; ++k) {
    const x = Math.round((canvas.width - 1) * k / 4);
    ctx.fillRect(x, 14, 1, 5);
    const v = state.lo + (state.hi - state.lo) * k / 4;
    const label = isUint(state.view) ? String(Math.round(v)) : num(Number(v.toPrecision(4)));
    ctx.textAlign = k === 0 ? 'left' : k === 4 ? 'right' : 'center';
    ctx.fillText(label, x, 31);
  }
  canvas.dataset.ticks = String(5);
}

// ---- the hovered texel, decoded by format -----------------------------------------------------

function decodeTexel(x, y) {
  const { texels, stencil, entry } = state.view;
  const b = entry.buffer;
  const raw = [];
  const i = (y * texels.width + x) * texels.channels;
  for (let c = 0; c < texels.channels; ++c) raw.push(texels.data[i + c]);
  let text = `(${x}, ${y}) ${entry.label} ${b.format}\n`;
  if (entry.isStencil) {
    text += `stencil ${raw[0]} = 0b${raw[0].toString(2).padStart(8, '0')}`;
  } else if (isDepthFormat(b.format)) {
    const d = raw[0];
    text += `depth ${d}`;
    if (b.format.startsWith('D24')) text += ` · D24 code ${Math.round(d * 16777215)} of 16777215`;
    if (stencil) {
      const s = stencil.data[(y * stencil.width + x) * stencil.channels];
      text += ` · stencil ${s} = 0b${s.toString(2).padStart(8, '0')}`;
    }
  } else if (texels.type === 'uint32') {
    if (b.name.startsWith('lightgrid')) text += `offset ${raw[0]}, count ${raw[1]} (the tile's list in the light index list)`;
    else if (b.name.startsWith('lightindex')) text += `light ${raw[0]}`;
    else if (b.name.endsWith('depthMask')) text += `2.5D depth mask ${maskBits(raw[0])} (GPU Pro 4 §5.6.1: ${popCount(raw[0])} of 32 depth cells hold geometry)`;
    else text += `uint ${raw.join(', ')}`;
  } else if (texels.type === 'uint8') {
    text += `codes ${raw.join(', ')} = ${raw.map((v) => num(v / 255)).join(', ')}`;
    if (b.format.endsWith('SRGB'))
      text += ` · linear ${raw.slice(0, 3).map((v) => { const c = v / 255; return num(c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4)); }).join(', ')}`;
    if (b.name === 'gbuffer.specular' && /3dgep/.test(technique().source || '') && raw.length === 4)
      text += ` · A packs specular power 2^(A x 10.5) = ${num(Math.pow(2, (raw[3] / 255) * 10.5))} (3dgep article §3.1.2)`;
  } else {
    text += `float ${raw.map((v) => num(v)).join(', ')}`;
  }
  return text;
}

const maskBits = (v) => `0b${(v >>> 0).toString(2).padStart(32, '0')}`;
const popCount = (v) => { let n = 0; for (let x = v >>> 0; x; x >>>= 1) n += x & 1; return n; };

// ---- tile light counts over the image (the tiled techniques' light grids) ---------------------

// The final light grids of the render (lightgrid.*: (offset, count) per tile) and the tile size.
function lightGrids() {
  return state.render.manifest.buffers.filter((b) => b.name.startsWith('lightgrid') && b.format.includes('UINT'));
}

async function setupTiles() {
  const grids = lightGrids();
  $('tileToggle').hidden = grids.length === 0;
  $('tiles').checked = false;
  $('tileBar').hidden = true;
  state.tileCounts = null;
  $('tileGrid').replaceChildren(...grids.map((b) => el('option', { value: b.name }, b.name)));
}

async function loadTileCounts() {
  const name = $('tileGrid').value;
  const b = lightGrids().find((x) => x.name === name);
  if (!$('tiles').checked || !b) { state.tileCounts = null; $('tileBar').hidden = true; drawOverlay(); return; }
  const texels = await fetchTexels(b.file);
  const width = state.render.manifest.width;
  const tileSizePx = Math.ceil(width / texels.width);
  let max = 0;
  for (let i = 0; i < texels.width * texels.height; ++i) max = Math.max(max, texels.data[i * texels.channels + 1]);
  state.tileCounts = { texels, tileSizePx, max };
  drawTileBar();
  drawOverlay();
}

// The tile overlay's scale: the heat ramp from 0 to the largest count, integer ticks.
function drawTileBar() {
  const canvas = $('tileBar');
  canvas.hidden = false;
  canvas.width = canvas.clientWidth || 600;
  const ctx = canvas.getContext('2d');
  const { max } = state.tileCounts;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  for (let x = 0; x < canvas.width; ++x) {
    const [r, g, b] = heat(x / (canvas.width - 1));
    ctx.fillStyle = `rgb(${r},${g},${b})`;
    ctx.fillRect(x, 0, 1, 16);
  }
  ctx.fillStyle = '#d8dbe0';
  ctx.font = '11px system-ui';
  const ticks = Math.min(max, 4);
  for (let k = 0; k <= ticks; ++k) {
    const x = Math.round((canvas.width - 1) * (ticks ? k / ticks : 0));
    ctx.fillRect(x, 14, 1, 5);
    ctx.textAlign = k === 0 ? 'left' : k === ticks ? 'right' : 'center';
    ctx.fillText(`${Math.round(max * (ticks ? k / ticks : 0))}${k === ticks ? ' lights in the tile' : ''}`, x, 31);
  }
  canvas.dataset.max = String(max);
}

function pixelAt(event) {
  const rect = $('overlay').getBoundingClientRect();
  const x = Math.floor((event.clientX - rect.left - state.panX) / state.zoom);
  const y = Math.floor((event.clientY - rect.top - state.panY) / state.zoom);
  if (!state.view || x < 0 || y < 0 || x >= state.view.texels.width || y >= state.view.texels.height) return null;
  return [x, y];
}

// The picked pixel, and for the tiled techniques its tile's rectangle, over the image.
function drawOverlay() {
  const canvas = $('overlay');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (state.tileCounts) {
    const { texels, tileSizePx, max } = state.tileCounts;
    const s = tileSizePx * state.zoom;
    ctx.globalAlpha = 0.5;
    for (let ty = 0; ty < texels.height; ++ty)
      for (let tx = 0; tx < texels.width; ++tx) {
        const count = texels.data[(ty * texels.width + tx) * texels.channels + 1];
        const [r, g, b] = heat(max ? count / max : 0);
        ctx.fillStyle = `rgb(${r},${g},${b})`;
        ctx.fillRect(state.panX + tx * s, state.panY + ty * s, s, s);
      }
    ctx.globalAlpha = 1;
  }
  if (!state.picked) return;
  const [x, y] = state.picked;
  const tile = state.probe && state.probe.tile;
  if (tile && tile.tileSizePx) {
    ctx.strokeStyle = '#7fb0ff';
    ctx.lineWidth = 1;
    const s = tile.tileSizePx * state.zoom;
    ctx.strokeRect(state.panX + tile.tile[0] * s + 0.5, state.panY + tile.tile[1] * s + 0.5, s, s);
  }
  // The reach of the lights that lit the pixel (or, tiled, those in its tile's list): each light's
  // range sphere bounded on screen (the manifest's lightExtents), dashed, with its name.
  const extents = state.render.manifest.lightExtents || [];
  for (const index of state.probeLights || []) {
    const e = extents[index];
    if (!e || !e.rectWindow) continue;
    const [x0, y0, x1, y1] = e.rectWindow;
    if (x1 <= x0 || y1 <= y0) continue;
    ctx.setLineDash([6, 4]);
    ctx.strokeStyle = '#ffd060';
    ctx.lineWidth = 1;
    ctx.strokeRect(state.panX + x0 * state.zoom, state.panY + y0 * state.zoom, (x1 - x0) * state.zoom, (y1 - y0) * state.zoom);
    ctx.setLineDash([]);
    ctx.fillStyle = '#ffd060';
    ctx.font = '12px system-ui';
    ctx.fillText(`${e.light} ${e.name}`, state.panX + x0 * state.zoom + 3, state.panY + y0 * state.zoom + 13);
  }
  drawTilePlanes(ctx, tile);
  ctx.strokeStyle = '#ff5050';
  ctx.lineWidth = 2;
  ctx.strokeRect(state.panX + x * state.zoom - 2, state.panY + y * state.zoom - 2, Math.max(state.zoom, 1) + 4, Math.max(state.zoom, 1) + 4);
}

// The tile's frustum side planes as the lines where they cut the image: each plane (N, d) passes
// through the eye, so a view ray (x_ndc tan(fovX/2), y_ndc tan(fovY/2), -1) lies in it where
// N.x x_ndc tanX + N.y y_ndc tanY - N.z = 0. The 3dgep planes run along the tile's edges; the Intel
// 2010 sample's (ERRATA.md #12) enclose the 2x2 tiles around it. Perspective cameras only.
function drawTilePlanes(ctx, tile) {
  const camera = state.render.manifest.camera || {};
  const lines = [];
  if (tile && tile.frustumPlanes && camera.projection === 'perspective') {
    const { width, height } = state.render.manifest;
    const tanY = Math.tan((camera.fovYDeg * Math.PI) / 360), tanX = tanY * (width / height);
    const toWindow = (xn, yn) => [(xn * 0.5 + 0.5) * width, (0.5 - yn * 0.5) * height];
    for (const [nx, ny, nz] of tile.frustumPlanes) {
      const a = nx * tanX, b = ny * tanY;
      if (Math.abs(a) >= Math.abs(b) && a !== 0) lines.push([toWindow((nz - b * 1) / a, 1), toWindow((nz + b) / a, -1)]);
      else if (b !== 0) lines.push([toWindow(-1, (nz + a) / b), toWindow(1, (nz - a) / b)]);
    }
    ctx.strokeStyle = '#60e0ff';
    ctx.lineWidth = 1;
    for (const [[x0, y0], [x1, y1]] of lines) {
      ctx.beginPath();
      ctx.moveTo(state.panX + x0 * state.zoom, state.panY + y0 * state.zoom);
      ctx.lineTo(state.panX + x1 * state.zoom, state.panY + y1 * state.zoom);
      ctx.stroke();
    }
  }
  $('overlay').dataset.planeLines = JSON.stringify(lines.map((l) => l.flat().map((v) => Number(v.toFixed(3)))));
}

// ---- a pixel's history ------------------------------------------------------------------------

const lightLabel = (names, index) => (index === 'ambient' ? 'ambient' : `light ${index}${names[index] ? ` '${names[index]}'` : ''}`);

function historyEvent(e, names) {
  const div = el('div', { class: 'event' });
  const where = `${e.pass}${e.light !== undefined ? ` · light ${e.light} ${e.step || ''}` : ''}`;
  if (e.draw !== undefined || e.compute) {
    div.classList.add(e.shaded ? 'shaded' : 'rejected');
    if (e.draw !== undefined) div.dataset.draw = String(e.draw);
    const title = e.compute ? `${where}: compute thread` : `${where}: draw ${e.draw}, primitive ${e.primitive} (${e.face} face)`;
    div.append(el('div', { class: 'title' }, title));
    const facts = [];
    if (e.coverage !== undefined) facts.push(`coverage ${e.coverage}`);
    if (e.z !== undefined) facts.push(`z ${num(e.z)}`);
    if (e.test) facts.push(e.test);
    if (e.stencil) facts.push(`stencil ${JSON.stringify(e.stencil)}`);
    facts.push(e.discarded ? 'discarded' : e.shaded ? 'shaded' : 'not shaded');
    div.append(el('div', { class: 'mono' }, facts.join(' · ')));
    for (const input of e.inputs || []) div.append(el('div', { class: 'mono' }, `in  ${input.name} ${vec(input.value)}`));
    if (e.output !== undefined) div.append(el('div', { class: 'mono' }, `out ${JSON.stringify(e.output)}`));
    if (e.surface) {
      const m = e.surface;
      div.append(el('div', { class: 'mono', 'data-surface': 'true' },
        `material diffuse ${vec(m.diffuse)} (textures sampled) alpha ${num(m.alpha)} ambient ${vec(m.ambient)} emissive ${vec(m.emissive)} specular ${vec(m.specular)} power ${num(m.specularPower)}`));
    }
    for (const t of e.lights || []) {
      const line = el('div', { class: `light mono${t.none ? ' nothing' : ''}`, 'data-light': String(t.light) });
      const added = t.added ? `added ${vec(t.added)}` : `diffuse ${vec(t.diffuse)} specular ${vec(t.specular)}`;
      line.textContent = `${lightLabel(names, t.light)}: ${t.none ? `nothing: ${t.none}` : added} (N.L ${num(t.nDotL)}${t.distance !== undefined ? `, distance ${num(t.distance)}` : ''})`;
      div.append(line);
    }
    const texel = (v) => vec(Array.isArray(v) ? v : v.values);
    if (e.color) div.append(el('div', { class: 'mono' }, `colour ${texel(e.color.before)} -> ${texel(e.color.after)}`));
  } else {
    div.dataset.buffer = e.buffer;
    const value = (v) => (Array.isArray(v) ? vec(v) : v && v.values ? vec(v.values) : v && v.depth !== undefined ? `depth ${num(v.depth)} stencil ${v.stencil}` : JSON.stringify(v));
    div.append(el('div', { class: 'mono' }, `${where}: ${e.buffer} ${e.before !== undefined ? value(e.before) + ' -> ' : ''}${value(e.after)}`));
  }
  return div;
}

async function probe(x, y) {
  state.picked = [x, y];
  drawOverlay();
  $('historyHint').textContent = `Pixel (${x}, ${y}): running the probe...`;
  try {
    const history = await api(`/api/probe/${state.render.id}?x=${x}&y=${y}`);
    state.probe = history;
    const names = history.lightNames || [];
    const lit = new Set(history.tile ? history.tile.lights : []);
    for (const e of history.events) for (const t of e.lights || []) if (!t.none && typeof t.light === 'number') lit.add(t.light);
    state.probeLights = [...lit].sort((a, b) => a - b);
    $('overlay').dataset.extents = state.probeLights.filter((i) => ((state.render.manifest.lightExtents || [])[i] || {}).rectWindow).join(',');
    const body = $('historyBody');
    body.replaceChildren();
    body.dataset.pixel = `${x},${y}`;
    for (const e of history.events) body.append(historyEvent(e, names));
    if (history.tile) {
      const t = history.tile;
      const div = el('div', { class: 'event', 'data-tile': t.tile.join(',') });
      div.append(el('div', { class: 'title' }, `tile (${t.tile.join(', ')}), ${t.tileSizePx} px: ${t.listCount} lights in its list`));
      div.append(el('div', { class: 'mono' }, `lights ${t.lights.map((i) => lightLabel(names, i)).join(', ')}`));
      if (t.culled !== undefined) div.append(el('div', { class: 'mono' }, `${t.culled} of the scene's lights culled from this tile`));
      for (const p of t.frustumPlanes || []) div.append(el('div', { class: 'mono' }, `plane ${vec(p)}`));
      if (t.depthRange) div.append(el('div', { class: 'mono' }, `depth range ${vec(t.depthRange)} (view-space distance)`));
      const maskBuffer = state.render.manifest.buffers.find((b) => b.name.endsWith('depthMask'));
      if (maskBuffer) {
        const mask = await fetchTexels(maskBuffer.file);
        const v = mask.data[(t.tile[1] * mask.width + t.tile[0]) * mask.channels];
        div.append(el('div', { class: 'mono', 'data-mask': String(v) }, `2.5D depth mask ${maskBits(v)}: ${popCount(v)} of 32 cells hold geometry (GPU Pro 4 §5.6.1)`));
      }
      body.append(div);
    }
    $('historyHint').textContent = `Pixel (${x}, ${y}) through the frame, in pass and draw order:`;
    drawOverlay();
  } catch (e) {
    $('historyHint').textContent = `Pixel (${x}, ${y}): ${e.message}`;
  }
}

// ---- deferred lighting, light by light --------------------------------------------------------

function setupLightSteps() {
  const steps = state.render.manifest.lightSteps;
  const section = $('lightSteps');
  if (!steps || Object.keys(steps).length === 0) { section.hidden = true; return; }
  section.hidden = false;
  const lights = Object.keys(steps).map(Number).sort((a, b) => a - b);
  const slider = $('lightSlider');
  slider.min = String(lights[0]);
  slider.max = String(lights[lights.length - 1]);
  slider.value = String(state.render.defaultLight !== undefined ? state.render.defaultLight : lights[0]);
  const total = state.render.manifest.lights;
  $('lightStepsNote').textContent = typeof total === 'number' && total > lights.length
    ? `steps kept for lights ${lights[0]}..${lights[lights.length - 1]} of the scene's ${total} (tessera serve --light-steps N keeps more)` : '';
  showLight(Number(slider.value));
}

function stepPicture(step, name, caption) {
  const fig = el('figure');
  const b = step.buffers.find((x) => x.name === name || (name === 'stencil' && x.stencilFile));
  if (!b) return null;
  const view = (b.views || []).find((v) => (name === 'stencil' ? v.file.endsWith('.stencil.png') : true));
  const file = view ? view.file : b.file;
  fig.append(el('img', { src: `/api/files/${state.render.id}/${urlPath(filePath(step.folder, file))}`, alt: caption, 'data-step-file': filePath(step.folder, file) }));
  fig.append(el('figcaption', {}, caption));
  return fig;
}

// The pixels light `light` changed: the back buffer after its shade step against before it.
async function shadedPicture(light, steps) {
  const lights = Object.keys(steps).map(Number).sort((a, b) => a - b);
  const index = lights.indexOf(light);
  const after = steps[light].shade;
  const before = index > 0 ? steps[lights[index - 1]].shade : state.render.manifest.after[passBeforeLights()];
  if (!after || !before) return null;
  const find = (s) => s.buffers.find((b) => b.name === 'backbuffer');
  const [a, b] = await Promise.all([fetchTexels(filePath(after.folder, find(after).file)), fetchTexels(filePath(before.folder, find(before).file))]);
  const canvas = el('canvas', { width: String(a.width), height: String(a.height) });
  const ctx = canvas.getContext('2d');
  const image = ctx.createImageData(a.width, a.height);
  let changed = 0;
  for (let p = 0; p < a.width * a.height; ++p) {
    let differs = false;
    for (let c = 0; c < a.channels; ++c) differs = differs || a.data[p * a.channels + c] !== b.data[p * b.channels + c];
    changed += differs ? 1 : 0;
    const v = differs ? 255 : 40;
    image.data.set([v, differs ? 220 : 40, differs ? 120 : 40, 255], p * 4);
  }
  ctx.putImageData(image, 0, 0);
  canvas.dataset.changed = String(changed);
  const fig = el('figure');
  fig.append(canvas, el('figcaption', {}, `pixels this light changed: ${changed} (back buffer after its shade step against before it)`));
  return fig;
}

// Killzone 2's decision for a light: its occlusion query's count (killzone.samples, one texel per
// light, after the count step) against the "threshold" option: shaded only when the count exceeds it.
async function killzoneCount(light, step) {
  const b = step.buffers.find((x) => x.name === 'killzone.samples');
  if (!b) return el('p', {}, 'no killzone.samples buffer in this render');
  const texels = await fetchTexels(filePath(step.folder, b.file));
  const count = texels.data[light];  // row-major: light i at (i mod width, i / width)
  const option = technique().options.find((o) => o.key === 'threshold');
  const threshold = Number((state.render.manifest.options || {}).threshold ?? (option ? option.faithful : 0));
  const p = el('p', { id: 'killzoneCount', 'data-count': String(count), 'data-threshold': String(threshold) },
    `occlusion query: ${count} samples passed the count step; threshold ${threshold}: ${count > threshold ? 'shaded' : 'skipped (the light adds nothing)'}`);
  return p;
}

function passBeforeLights() {
  const passes = state.render.manifest.passes.map((p) => p.name);
  const i = passes.indexOf('lights');
  return i > 0 ? passes[i - 1] : passes[0];
}

async function showLight(light) {
  const steps = state.render.manifest.lightSteps;
  const names = state.probe ? state.probe.lightNames || [] : [];
  $('lightName').textContent = `${lightLabel(names, light)}${state.render.defaultLight === light ? ' (the light whose stencil shows the trick best)' : ''}`;
  const box = $('lightPictures');
  box.replaceChildren();
  box.dataset.light = String(light);
  const s = steps[light];
  const marking = s.count ? ['count', 'stencil after the count step (Killzone 2: lit where the count passes the threshold)']
    : s.unmark ? ['unmark', 'stencil after unmark: the pixels whose surface is inside the light volume keep their mark']
    : null;
  if (marking) {
    const fig = stepPicture(s[marking[0]], 'stencil', marking[1]);
    if (fig) box.append(fig);
  } else {
    box.append(el('p', {}, 'This light has no stencil steps (a full-screen pass: directional light).'));
  }
  if (s.count) box.append(await killzoneCount(light, s.count));
  const shaded = await shadedPicture(light, steps);
  if (shaded) box.append(shaded);
  if (s.shade) {
    const fig = stepPicture(s.shade, 'backbuffer', 'the accumulation after this light');
    if (fig) box.append(fig);
  }
}

// ---- compare two renders ----------------------------------------------------------------------

let errata = null;  // ERRATA.md's table rows by number (the server embeds the file)
async function erratumText(number) {
  if (!errata) {
    errata = {};
    const text = await (await fetch('/ERRATA.md')).text();
    for (const line of text.split('\n')) {
      const m = /^\| (\d+) \| (.*?) \| (.*?) \| (.*?) \| (.*?) \|$/.exec(line);
      if (m) errata[m[1]] = { text: m[2], faithful: m[3], correction: m[4], test: m[5] };
    }
  }
  return errata[String(number)];
}
const plain = (markdown) => markdown.replace(/\*\*|`/g, '');

async function fillCompareLists() {
  const status = await api('/api/status');
  const done = status.renders.filter((r) => r.status === 'done');
  for (const [id, pick] of [['compareA', done.length > 1 ? done[done.length - 2].id : null], ['compareB', state.render.id]]) {
    const select = $(id);
    select.replaceChildren(...done.map((r) => el('option', { value: String(r.id) }, `#${r.id}: ${r.args.slice(1).join(' ') || r.args[0]}`)));
    if (pick !== null) select.value = String(pick);
  }
  const t = technique();
  const current = state.render.manifest.options || {};
  $('erratumPick').replaceChildren(...t.options.filter((o) => o.erratum && o.corrected && String(current[o.key] ?? faithfulValue(o)) !== o.corrected)
    .map((o) => el('option', { value: o.key }, `#${o.erratum} ${o.key}: ${faithfulValue(o)} -> ${o.corrected}`)));
  $('erratumRun').disabled = $('erratumPick').options.length === 0;
}

// tessera diff of two renders' back buffers: both pictures, the heat map, the statistics, and
// the ERRATA.md rows of the options in which the two renders differ.
async function compare(a, b) {
  const box = $('compareBody');
  box.replaceChildren(el('p', {}, `comparing #${a} with #${b}...`));
  try {
    const [d, ra, rb] = await Promise.all([api(`/api/diff/${a}/${b}`), api(`/api/render/${a}`), api(`/api/render/${b}`)]);
    box.replaceChildren();
    for (const [r, caption] of [[ra, `#${a}`], [rb, `#${b}`]]) {
      const fig = el('figure');
      fig.append(el('img', { src: `/api/files/${r.id}/backbuffer.png`, alt: caption }), el('figcaption', {}, `${caption}: ${r.manifest.technique} ${r.manifest.width}x${r.manifest.height}`));
      box.append(fig);
    }
    const heat = el('figure');
    heat.append(el('img', { src: d.heatmap, alt: 'difference heat map', id: 'diffHeatmap' }),
      el('figcaption', {}, `each pixel's largest channel difference: black equal, then blue, green, yellow, white = max abs ${num(d.max_abs)}`));
    box.append(heat);
    const table = el('table', { id: 'diffStats' });
    for (const [k, v] of [['max abs', d.max_abs], ['mean abs', d.mean_abs], ['rmse', d.rmse], ['psnr dB', d.psnr_db === null ? 'inf (equal)' : d.psnr_db],
      ['differing pixels', `${d.differing_pixels} of ${d.pixels}`]]) {
      const tr = el('tr');
      tr.append(el('td', {}, k), el('td', {}, typeof v === 'number' ? num(v) : String(v)));
      table.append(tr);
    }
    box.append(table);
    const options = state.techniques.find((t) => t.id === rb.manifest.technique) || { options: [] };
    const oa = ra.manifest.options || {}, ob = rb.manifest.options || {};
    for (const o of options.options) {
      const va = String(oa[o.key] ?? faithfulValue(o)), vb = String(ob[o.key] ?? faithfulValue(o));
      if (va === vb || !o.erratum || ra.manifest.technique !== rb.manifest.technique) continue;
      const row = await erratumText(o.erratum);
      const div = el('div', { class: 'erratum', 'data-erratum': String(o.erratum) });
      div.append(el('div', { class: 'title' }, `${o.key}: ${va} in #${a}, ${vb} in #${b} — ERRATA.md #${o.erratum}`));
      if (row) div.append(el('div', {}, plain(row.text)), el('div', { class: 'nothing' }, `shown by the test ${plain(row.test)}`));
      box.append(div);
    }
    box.dataset.differing = String(d.differing_pixels);
    box.dataset.pair = `${a}-${b}`;  // complete (tests wait for it)
  } catch (e) {
    box.replaceChildren(el('p', {}, e.message));
  }
}

// Re-renders the current frame with one erratum's option corrected, then compares the two.
async function renderCorrected() {
  const key = $('erratumPick').value;
  const t = technique();
  const o = t.options.find((x) => x.key === key);
  const before = state.render.id;
  const m = state.render.manifest;
  const options = {};
  for (const x of t.options) {
    const value = (m.options || {})[x.key];
    if (value !== undefined && (String(value) !== faithfulValue(x) || commandLineOptions().has(x.key))) options[x.key] = value;
  }
  options[key] = o.kind === 'bool' || o.kind === 'integer' ? JSON.parse(o.corrected) : o.corrected;
  const body = { technique: m.technique, width: m.width, height: m.height, msaa: m.msaa || 1, precision: m.precision || 'exact', options };
  try {
    const { id } = await api('/api/render', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
    await waitFor(id);
    if (state.render.id === id) await compare(before, id);
  } catch (e) {
    setStatus(e.message, true);
  }
}

// ---- wiring -----------------------------------------------------------------------------------

function wire() {
  $('controls').addEventListener('submit', submitRender);
  $('technique').addEventListener('change', () => fillOptions($('technique').value, {}));
  $('cancel').addEventListener('click', () => api('/api/cancel', { method: 'POST' }).catch((e) => setStatus(e.message, true)));
  for (const id of ['rangeLo', 'rangeHi']) $(id).addEventListener('change', () => {
    state.lo = Number($('rangeLo').value);
    state.hi = Number($('rangeHi').value);
    if (!(state.hi > state.lo)) state.hi = state.lo + 1;
    draw();
  });
  $('rangeAuto').addEventListener('click', () => { fitRange(); draw(); });
  $('srgb').addEventListener('change', draw);
  $('zoomFit').addEventListener('click', () => { fitView(); paint(); });
  $('tiles').addEventListener('change', () => loadTileCounts().catch((e) => setStatus(e.message, true)));
  $('tileGrid').addEventListener('change', () => loadTileCounts().catch((e) => setStatus(e.message, true)));
  $('lightSlider').addEventListener('input', () => showLight(Number($('lightSlider').value)));
  $('compareRun').addEventListener('click', () => compare(Number($('compareA').value), Number($('compareB').value)));
  $('erratumRun').addEventListener('click', renderCorrected);
  const overlay = $('overlay');
  let drag = null;
  overlay.addEventListener('mousedown', (e) => { drag = { x: e.clientX, y: e.clientY, panX: state.panX, panY: state.panY, moved: false }; });
  window.addEventListener('mouseup', (e) => {
    if (drag && !drag.moved) { const p = pixelAt(e); if (p) probe(p[0], p[1]); }
    drag = null;
  });
  overlay.addEventListener('mousemove', (e) => {
    if (drag) {
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
      if (drag.moved) { state.panX = drag.panX + dx; state.panY = drag.panY + dy; paint(); }
    }
    const p = pixelAt(e);
    $('hover').textContent = p ? decodeTexel(p[0], p[1]) : ' ';
  });
  overlay.addEventListener('wheel', (e) => {
    e.preventDefault();
    const rect = overlay.getBoundingClientRect();
    const mx = e.clientX - rect.left, my = e.clientY - rect.top;
    const factor = e.deltaY < 0 ? 2 : 0.5;
    const zoom = Math.max(0.125, Math.min(64, state.zoom * factor));
    state.panX = mx - (mx - state.panX) * (zoom / state.zoom);
    state.panY = my - (my - state.panY) * (zoom / state.zoom);
    state.zoom = zoom;
    paint();
  }, { passive: false });
  window.addEventListener('resize', paint);
}

async function main() {
  wire();
  try {
    state.techniques = await api('/api/techniques');
    const status = await api('/api/status');
    if (!status.latestDone) throw new Error('the server has no finished render yet');
    state.firstArgs = status.renders.length ? status.renders[0].args : [];
    await loadRender(status.latestDone);
    document.body.dataset.ready = 'true';
  } catch (e) {
    setStatus(e.message, true);
  }
}

main();
