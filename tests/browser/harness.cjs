// Shared by the browser test, the browser bench and the screenshot script: start
// `filmsplat view`, launch the headless chromium, wait for pictures, compare them.
'use strict';

const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const { chromium } = require(process.env.FILMSPLAT_PLAYWRIGHT);

const BIN = process.env.FILMSPLAT_BIN;
const LONG = 180_000; // ms: generous, for a loaded 2-core machine

function tempDir(name) {
  return fs.mkdtempSync(path.join(os.tmpdir(), `filmsplat-${name}-`));
}

// Starts `filmsplat view ARGS --port 0` and resolves with its URL once printed.
function startViewer(args) {
  return new Promise((resolve, reject) => {
    const proc = spawn(BIN, ['view', ...args, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '';
    let err = '';
    const timer = setTimeout(() => reject(new Error(`no URL after ${LONG} ms: ${out}${err}`)), LONG);
    proc.stdout.on('data', (d) => {
      out += d;
      const m = /(http:\/\/\S+\?token=[0-9a-f]+)/.exec(out);
      if (m) {
        clearTimeout(timer);
        resolve({
          proc, url: m[1], output: () => out,
          // Ctrl-C; resolves with the exit code.
          stop: () => new Promise((done) => { proc.once('exit', (code) => done(code)); proc.kill('SIGINT'); }),
        });
      }
    });
    proc.stderr.on('data', (d) => { err += d; });
    proc.once('exit', (code) => { clearTimeout(timer); reject(new Error(`view exited ${code}: ${out}${err}`)); });
  });
}

// The headless chromium with the project's flags and a new empty profile.
async function launch(viewport) {
  const profile = tempDir('chromium-profile');
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    viewport,
    acceptDownloads: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = context.pages()[0] || (await context.newPage());
  page.setDefaultTimeout(LONG);
  return { context, page, close: async () => { await context.close(); fs.rmSync(profile, { recursive: true, force: true }); } };
}

// Waits until the page shows a final picture newer than `after` for which `extra` holds
// (checked on the <img>'s data attributes), and returns its data attributes.
async function waitFinal(page, after = -1, extra = {}) {
  await page.waitForFunction(([after, extra]) => {
    const d = document.getElementById('picture').dataset;
    if (d.pass !== 'final' || Number(d.version) <= after) return false;
    return Object.entries(extra).every(([k, v]) => d[k] === String(v));
  }, [after, extra], { timeout: LONG, polling: 50 });
  return page.evaluate(() => ({ ...document.getElementById('picture').dataset }));
}

// The RGBA pixels of the picture on screen (or of a PNG given as base64), drawn at its size.
async function pixels(page, pngBase64) {
  return page.evaluate(async (b64) => {
    let img = document.getElementById('picture');
    if (b64) {
      img = new Image();
      img.src = 'data:image/png;base64,' + b64;
      await img.decode();
    }
    const c = document.createElement('canvas');
    c.width = img.naturalWidth;
    c.height = img.naturalHeight;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    return { width: c.width, height: c.height, data: Array.from(g.getImageData(0, 0, c.width, c.height).data) };
  }, pngBase64 || null);
}

// Mean absolute difference per channel (0..255) of two same-size pictures.
function meanDiff(a, b) {
  if (a.width !== b.width || a.height !== b.height) throw new Error(`sizes differ: ${a.width}x${a.height} vs ${b.width}x${b.height}`);
  let s = 0;
  for (let i = 0; i < a.data.length; i++) s += Math.abs(a.data[i] - b.data[i]);
  return s / a.data.length;
}

async function drag(page, from, to, shift = false) {
  await page.mouse.move(from[0], from[1]);
  if (shift) await page.keyboard.down('Shift');
  await page.mouse.down();
  await page.mouse.move(to[0], to[1], { steps: 12 });
  await page.mouse.up();
  if (shift) await page.keyboard.up('Shift');
}

module.exports = { BIN, LONG, tempDir, startViewer, launch, waitFinal, pixels, meanDiff, drag };
