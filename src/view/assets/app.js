// filmsplat view: the page. Orbit/zoom/pan a camera, ask the server for pictures: small and
// fast while the camera moves, then refined (half size at 1 spp, then the preset's quality)
// once it stops. A newer picture aborts the one in flight (the server cancels its render).
'use strict';

const TOKEN = new URLSearchParams(location.search).get('token') || '';
const CLIENT = 'tab-' + Array.from({ length: 4 }, () => Math.random().toString(36).slice(2, 8)).join('');
const MOVE_SCALE = 0.25;   // picture side while moving, of the window's
const DRAFT_SCALE = 0.5;   // first refinement
const IDLE_MS = 150;       // quiet time that ends a move
const PLAY_FPS = 24;
const $ = (id) => document.getElementById(id);

const st = {
  scene: null, frame: 0, view: 'shaded', primitive: 'scene', preset: 'scene', exposure: 0,
  target: [0, 0, 0], dist: 1, yaw: 0, pitch: 0, fov: 40, up: [0, 1, 0], basis: null,
  exact: null,           // the scene's own camera numbers until the first move
  version: 0,            // bumped by every change of what the picture should show
  playing: false,
};
// What is on screen, for the status line and for tests.
const shown = { version: -1, pass: '', width: 0, height: 0, ms: 0, spp: 0, moves: 0, log: [], releasedAt: 0 };
window.filmsplat = { st, shown };

// ---- vectors ----
const add = (a, b) => a.map((v, i) => v + b[i]);
const sub = (a, b) => a.map((v, i) => v - b[i]);
const mul = (a, s) => a.map((v) => v * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => { const l = Math.hypot(...a) || 1; return mul(a, 1 / l); };

// The orbit: yaw about the scene's up, pitch toward it, around the target.
function setCamera(cam) {
  const u = norm(cam.up);
  const d = sub(cam.position, cam.look_at);
  st.dist = Math.hypot(...d) || 1;
  let flat = sub(d, mul(u, dot(d, u)));
  if (Math.hypot(...flat) < 1e-9 * st.dist) flat = Math.abs(u[0]) < 0.9 ? cross(u, [1, 0, 0]) : cross(u, [0, 0, 1]);
  const e2 = norm(flat), e1 = cross(u, e2);
  st.basis = { u, e1, e2 };
  st.target = cam.look_at.slice();
  st.up = cam.up.slice();
  st.fov = cam.fov;
  st.yaw = 0;
  st.pitch = Math.asin(Math.max(-1, Math.min(1, dot(d, u) / st.dist)));
  st.exact = cam;
}

function camera() {
  if (st.exact) return st.exact;
  const { u, e1, e2 } = st.basis;
  const c = Math.cos(st.pitch);
  const dir = add(add(mul(e1, c * Math.sin(st.yaw)), mul(e2, c * Math.cos(st.yaw))), mul(u, Math.sin(st.pitch)));
  return { position: add(st.target, mul(dir, st.dist)), look_at: st.target, up: st.up, fov: st.fov };
}

function orbit(dx, dy) {
  st.exact = null;
  st.yaw -= dx * 0.006;
  st.pitch = Math.max(-1.55, Math.min(1.55, st.pitch + dy * 0.006));
  moved();
}

function pan(dx, dy) {
  const cam = camera();
  st.exact = null;
  const fwd = norm(sub(cam.look_at, cam.position));
  const right = norm(cross(fwd, st.basis.u));
  const upv = cross(right, fwd);
  const perPx = 2 * st.dist * Math.tan(st.fov * Math.PI / 360) / Math.max(1, innerHeight);
  st.target = add(st.target, add(mul(right, -dx * perPx), mul(upv, dy * perPx)));
  moved();
}

function zoom(factor) {
  st.exact = null;
  st.dist = Math.max(1e-6, st.dist * factor);
  moved();
}

// ---- requests ----
function query(extra) {
  const c = camera();
  const p = new URLSearchParams({
    token: TOKEN, client: CLIENT, frame: st.frame, view: st.view, primitive: st.primitive,
    preset: st.preset, exposure: st.exposure, pos: c.position.join(','), look: c.look_at.join(','),
    up: c.up.join(','), fov: c.fov, ...extra,
  });
  return p.toString();
}

function size(scale) {
  const max = st.scene ? st.scene.max_side : 4096;
  const w = Math.max(16, Math.min(max, Math.round(innerWidth * scale)));
  const h = Math.max(16, Math.min(max, Math.round(innerHeight * scale)));
  return { w, h };
}

let inflight = null;   // { ctrl, pass, version }
let moveWanted = false;
let idleTimer = 0;
let lastUrl = '';
const moveTimes = [];

function showError(text) {
  const e = $('error');
  e.textContent = text;
  e.hidden = !text;
}

async function fetchPicture(pass, scale, version) {
  const ctrl = new AbortController();
  if (inflight) inflight.ctrl.abort();
  inflight = { ctrl, pass, version };
  const { w, h } = size(scale);
  const t0 = performance.now();
  const slow = setTimeout(() => setStatus(`preparing frame ${label()} (${st.primitive}, ${st.preset})…`), 400);
  try {
    const r = await fetch('/api/render?' + query({ pass, w, h }), { signal: ctrl.signal });
    if (!r.ok) {
      const text = (await r.text()).trim();
      if (r.status !== 409) showError(`${r.status}: ${text}`);
      return false;
    }
    const blob = await r.blob();
    if (version !== st.version && pass !== 'move') return false;
    // A moving picture is decoded while the next one renders; a refined one before the next.
    const showing = show(blob, pass, version, w, h, r.headers);
    if (pass !== 'move') await showing;
    showError('');
    if (pass === 'move') {
      moveTimes.push(performance.now());
      while (moveTimes.length && moveTimes[0] < performance.now() - 1000) moveTimes.shift();
    }
    shown.wall = performance.now() - t0;
    return true;
  } catch (e) {
    if (e.name !== 'AbortError') showError(String(e));
    return false;
  } finally {
    clearTimeout(slow);
    if (inflight && inflight.ctrl === ctrl) inflight = null;
  }
}

function show(blob, pass, version, w, h, headers) {
  return new Promise((resolve) => {
    const img = $('picture');
    const url = URL.createObjectURL(blob);
    img.onload = () => {
      if (lastUrl) URL.revokeObjectURL(lastUrl);
      lastUrl = url;
      Object.assign(shown, {
        version, pass, width: w, height: h,
        ms: Number(headers.get('X-Render-Ms')), spp: Number(headers.get('X-Spp')),
      });
      if (pass === 'move') shown.moves++;
      shown.log.push({ pass, at: performance.now() });
      if (shown.log.length > 1000) shown.log.shift();
      img.dataset.pass = pass;
      img.dataset.version = version;
      img.dataset.frame = st.frame;
      img.dataset.view = st.view;
      setStatus();
      resolve();
    };
    img.onerror = () => resolve();
    img.src = url;
  });
}

// The camera (or frame) is moving: small pictures as fast as they come, one at a time.
function moved() {
  st.version++;
  clearTimeout(idleTimer);
  idleTimer = setTimeout(refine, IDLE_MS);
  if (inflight && inflight.pass !== 'move') inflight.ctrl.abort();
  if (inflight && inflight.pass === 'move') { moveWanted = true; return; }
  moveLoop();
}

async function moveLoop() {
  moveWanted = false;
  await fetchPicture('move', MOVE_SCALE, st.version);
  if (moveWanted) moveLoop();
  else if (st.playing) { prepareAhead(); nextPlayFrame(); }
}

// Something changed that needs no motion (view, preset, exposure, size): refine at once.
function changed() {
  st.version++;
  clearTimeout(idleTimer);
  refine();
}

async function refine() {
  if (st.playing) return;
  const version = st.version;
  const steps = st.view === 'shaded' ? [['draft', DRAFT_SCALE], ['final', 1]] : [['final', 1]];
  for (const [pass, scale] of steps) {
    if (version !== st.version) return;
    if (!(await fetchPicture(pass, scale, version))) return;
  }
  prepareAhead();
}

// ---- frames ----
function label() { return st.scene ? st.scene.frames[st.frame] : ''; }

// The direction frames were last stepped in (0: never): the next frame that way is prepared
// while this one is looked at, so stepping or playing on finds it built.
let stepDir = 0;
let aheadAsked = '';
function prepareAhead() {
  if (!st.scene || st.scene.frames.length < 2 || stepDir === 0) return;
  const n = st.scene.frames.length;
  const next = (((st.frame + stepDir) % n) + n) % n;
  const key = new URLSearchParams({
    token: TOKEN, frame: next, view: st.view, primitive: st.primitive, preset: st.preset,
  }).toString();
  if (key === aheadAsked) return;
  aheadAsked = key;
  fetch('/api/prepare?' + key).catch(() => {});
}

function setFrame(i, moving) {
  const n = st.scene.frames.length;
  if (i !== st.frame) stepDir = i > st.frame ? 1 : -1;
  st.frame = ((i % n) + n) % n;
  $('frame').value = st.frame;
  $('frame-label').textContent = `frame ${label()} (${st.frame + 1}/${n})`;
  if (moving) moved(); else changed();
}

let playTimer = 0;
let playStart = 0;
function nextPlayFrame() {
  const wait = Math.max(0, 1000 / PLAY_FPS - (performance.now() - playStart));
  clearTimeout(playTimer);
  playTimer = setTimeout(() => { playStart = performance.now(); setFrame(st.frame + 1, true); }, wait);
}

function togglePlay() {
  if (!st.scene || st.scene.frames.length < 2) return;
  st.playing = !st.playing;
  $('play').innerHTML = st.playing ? '&#10074;&#10074;' : '&#9654;';
  if (st.playing) { playStart = performance.now(); setFrame(st.frame + 1, true); }
  else { clearTimeout(playTimer); changed(); }
}

// ---- status ----
function setStatus(text) {
  if (text) { $('status').textContent = text; return; }
  const fps = moveTimes.length;
  $('status').textContent = `frame ${label()} · ${shown.pass} ${shown.width}×${shown.height} · ` +
    `${shown.spp} spp · ${shown.ms.toFixed(0)} ms render` + (shown.pass === 'move' && fps > 1 ? ` · ${fps} pictures/s` : '');
}

// ---- copy camera, save ----
async function copyCamera() {
  const c = camera();
  const p = new URLSearchParams({ token: TOKEN, pos: c.position.join(','), look: c.look_at.join(','), up: c.up.join(','), fov: c.fov });
  // A sequence: the lines of a camera path's key at the frame shown.
  if (st.scene && st.scene.frames.length > 1 && /^\d+$/.test(label())) p.set('frame', st.frame);
  const r = await fetch('/api/camera?' + p);
  const text = await r.text();
  if (!r.ok) { showError(`${r.status}: ${text.trim()}`); return; }
  $('camera-text').value = text;
  $('camera-dialog').hidden = false;
  $('camera-text').select();
  let note = 'copied to the clipboard';
  try { await navigator.clipboard.writeText(text); } catch (e) {
    note = document.execCommand && document.execCommand('copy') ? 'copied to the clipboard' : 'select and copy them';
  }
  $('camera-note').textContent = note;
}

async function save() {
  const m = /^\s*(\d+)\s*[x×]\s*(\d+)\s*$/.exec($('save-size').value);
  if (!m) { showError('save size must be WIDTHxHEIGHT, e.g. 1920x1080'); return; }
  const [w, h] = [Number(m[1]), Number(m[2])];
  setStatus(`saving ${w}×${h}…`);
  const r = await fetch('/api/save?' + query({ w, h, client: CLIENT + '-save' }));
  if (!r.ok) { showError(`${r.status}: ${(await r.text()).trim()}`); setStatus(); return; }
  const name = /filename="([^"]+)"/.exec(r.headers.get('Content-Disposition') || '');
  const a = document.createElement('a');
  a.href = URL.createObjectURL(await r.blob());
  a.download = name ? name[1] : 'filmsplat.png';
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  setStatus(`saved ${a.download}`);
}

// ---- controls ----
function fill(select, items, value) {
  select.innerHTML = '';
  for (const v of items) {
    const o = document.createElement('option');
    o.value = o.textContent = v;
    select.appendChild(o);
  }
  select.value = value;
}

function cycle(select, step) {
  const n = select.options.length;
  select.selectedIndex = (select.selectedIndex + step + n) % n;
  select.dispatchEvent(new Event('change'));
}

function setExposure(ev) {
  st.exposure = Math.max(-6, Math.min(6, ev));
  $('exposure').value = st.exposure;
  $('exposure-value').textContent = st.exposure.toFixed(2);
  changed();
}

function wire() {
  const stage = $('stage');
  let drag = null;
  stage.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
    stage.setPointerCapture(e.pointerId);
    stage.classList.add('dragging');
  });
  stage.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const [dx, dy] = [e.clientX - drag.x, e.clientY - drag.y];
    drag.x = e.clientX; drag.y = e.clientY;
    if (dx === 0 && dy === 0) return;
    if (drag.pan || e.shiftKey) pan(dx, dy); else orbit(dx, dy);
  });
  const end = () => { if (drag) shown.releasedAt = performance.now(); drag = null; stage.classList.remove('dragging'); };
  stage.addEventListener('pointerup', end);
  stage.addEventListener('pointercancel', end);
  stage.addEventListener('contextmenu', (e) => e.preventDefault());
  stage.addEventListener('wheel', (e) => { e.preventDefault(); zoom(Math.exp(e.deltaY * 0.0015)); }, { passive: false });

  $('primitive').addEventListener('change', (e) => { st.primitive = e.target.value; changed(); });
  $('view').addEventListener('change', (e) => { st.view = e.target.value; changed(); });
  $('preset').addEventListener('change', (e) => { st.preset = e.target.value; changed(); });
  $('exposure').addEventListener('input', (e) => setExposure(Number(e.target.value)));
  $('frame').addEventListener('input', (e) => setFrame(Number(e.target.value), true));
  $('play').addEventListener('click', togglePlay);
  $('copy-camera').addEventListener('click', copyCamera);
  $('save').addEventListener('click', save);
  $('help-button').addEventListener('click', () => { $('help').hidden = !$('help').hidden; });
  $('camera-close').addEventListener('click', () => { $('camera-dialog').hidden = true; });
  let resizeTimer = 0;
  addEventListener('resize', () => { clearTimeout(resizeTimer); resizeTimer = setTimeout(changed, 200); });
  addEventListener('keydown', onKey);
}

function onKey(e) {
  if (e.key === 'Escape') { $('camera-dialog').hidden = true; $('help').hidden = true; return; }
  if (e.target.closest('input[type=text], input:not([type]), textarea, select') || e.ctrlKey || e.metaKey || e.altKey) return;
  const step = 20;
  const arrows = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] };
  if (arrows[e.key]) {
    const [dx, dy] = arrows[e.key];
    if (e.shiftKey) pan(dx, dy); else orbit(dx, dy);
  } else if (e.key === '+' || e.key === '=') zoom(1 / 1.15);
  else if (e.key === '-' || e.key === '_') zoom(1.15);
  else if (e.key === ' ') togglePlay();
  else if (e.key === ',') setFrame(st.frame - 1, false);
  else if (e.key === '.') setFrame(st.frame + 1, false);
  else if (e.key === 'v') cycle($('view'), 1);
  else if (e.key === 'V') cycle($('view'), -1);
  else if (e.key === 'p') cycle($('primitive'), 1);
  else if (e.key === 'q') cycle($('preset'), 1);
  else if (e.key === '[') setExposure(st.exposure - 0.25);
  else if (e.key === ']') setExposure(st.exposure + 0.25);
  else if (e.key === 'r') { setCamera(st.scene.camera); changed(); }
  else if (e.key === 'c') copyCamera();
  else if (e.key === 's') save();
  else if (e.key === '?' || e.key === 'h') $('help').hidden = !$('help').hidden;
  else return;
  e.preventDefault();
}

async function start() {
  wire();
  const r = await fetch('/api/scene?token=' + encodeURIComponent(TOKEN));
  if (!r.ok) { setStatus(''); showError(`${r.status}: ${(await r.text()).trim()}`); return; }
  const s = await r.json();
  st.scene = s;
  document.title = `filmsplat view: ${s.title}`;
  $('scene-title').textContent = `${s.title} · ${s.particles.toLocaleString('en')} particles`;
  fill($('primitive'), ['scene', ...s.primitives], 'scene');
  fill($('view'), s.views.includes(s.view) ? s.views : [...s.views, s.view], s.view);
  st.view = s.view;
  fill($('preset'), s.presets, 'scene');
  $('save-size').value = `${s.size[0]}x${s.size[1]}`;
  $('frame').max = s.frames.length - 1;
  $('timeline').hidden = s.frames.length < 2;
  st.exposure = s.exposure;
  $('exposure').value = s.exposure;
  $('exposure-value').textContent = s.exposure.toFixed(2);
  setCamera(s.camera);
  setFrame(0, false);
}

start();
