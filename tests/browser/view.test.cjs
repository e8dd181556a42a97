// End-to-end test of `filmsplat view` in headless chromium: load the page, drag and see the
// picture change, scrub a frame, switch to the thickness view, copy the camera and check that
// `filmsplat render` makes the same picture of the copied lines; save; the shortcut list.
// Run it with `bash tests/browser/run.sh` (installs chromium and playwright-core if missing).
'use strict';

const { execFileSync } = require('child_process');
const fs = require('fs');
const path = require('path');
const h = require('./harness.cjs');

const SCENE = '[input]\nsample = "bubble"\nparticles = 20000\n[render]\nwidth = 200\nheight = 120\n';
const VIEWPORT = { width: 640, height: 360 };

function check(cond, what) {
  if (!cond) throw new Error(`FAILED: ${what}`);
  console.log(`ok - ${what}`);
}

async function main() {
  const dir = h.tempDir('browser-test');
  const scene = path.join(dir, 'scene.toml');
  fs.writeFileSync(scene, SCENE);
  const viewer = await h.startViewer([scene, '--frames', '0..3']);
  const browser = await h.launch(VIEWPORT);
  const { page } = browser;
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  const prepared = [];
  page.on('request', (r) => {
    const u = new URL(r.url());
    if (u.pathname === '/api/prepare') prepared.push(u.searchParams.get('frame'));
  });
  try {
    await page.goto(viewer.url);
    let shown = await h.waitFinal(page);
    const first = await h.pixels(page);
    check(first.width === VIEWPORT.width && first.height === VIEWPORT.height, `the picture fills the window (${first.width}x${first.height})`);
    check(await page.isVisible('#timeline'), 'a sequence has a time slider');

    await h.drag(page, [420, 200], [500, 230]);
    shown = await h.waitFinal(page, Number(shown.version));
    const dragged = await h.pixels(page);
    check(h.meanDiff(first, dragged) > 2, `dragging orbits: the picture changed (mean difference ${h.meanDiff(first, dragged).toFixed(2)})`);

    await page.locator('#frame').fill('2');
    shown = await h.waitFinal(page, Number(shown.version), { frame: 2 });
    check((await page.textContent('#frame-label')).includes('frame 2'), 'scrubbing shows frame 2');
    const scrubbed = await h.pixels(page);
    check(h.meanDiff(dragged, scrubbed) > 0, 'frame 2 is another picture');
    // Scrubbed forward from 0 to 2 (the last of 0..3): once frame 2's final picture shows, the
    // next frame that way (wrapping round to 0) is prepared ahead.
    await page.waitForTimeout(300);
    check(prepared.includes('0'), `the next frame is prepared ahead (asked: ${JSON.stringify(prepared)})`);

    await page.selectOption('#view', 'thickness');
    shown = await h.waitFinal(page, Number(shown.version), { view: 'thickness' });
    const thickness = await h.pixels(page);
    check(h.meanDiff(scrubbed, thickness) > 10, 'the thickness view is a different picture');

    await page.click('#copy-camera');
    await page.waitForSelector('#camera-dialog:not([hidden])');
    const lines = await page.inputValue('#camera-text');
    // On a numbered sequence the lines are a camera path's key at the frame shown.
    check(/^\[\[camera\.key\]\]\nframe = 2\nposition = \[.+\]\nlook_at = \[.+\]\nfov = .+\n$/.test(lines), `copy camera gives the [[camera.key]] lines of frame 2 (${JSON.stringify(lines)})`);

    // The same view with `render`: the scene, the copied lines, frame 2, the window's size.
    const pasted = path.join(dir, 'pasted.toml');
    fs.writeFileSync(pasted, SCENE + lines);
    execFileSync(h.BIN, ['render', pasted, '--frames', '2..3', '--view', 'thickness', '--size',
      `${VIEWPORT.width}x${VIEWPORT.height}`, '-q', '-o', path.join(dir, 'render_{}.png')]);
    const rendered = await h.pixels(page, fs.readFileSync(path.join(dir, 'render_2.png')).toString('base64'));
    check(h.meanDiff(rendered, thickness) === 0, 'render of the copied lines gives exactly the picture shown');

    await page.keyboard.press('Escape');
    await page.fill('#save-size', '96x40');
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save')]);
    const saved = fs.readFileSync(await download.path());
    check(saved.readUInt32BE(16) === 96 && saved.readUInt32BE(20) === 40, `save downloads a 96x40 PNG (${download.suggestedFilename()})`);

    await page.mouse.click(500, 250);
    await page.keyboard.press('?');
    check(await page.isVisible('#help'), 'the shortcut list opens with ?');
    check(errors.length === 0, `no errors in the page (${errors.join('; ')})`);
  } finally {
    await browser.close();
    const code = await viewer.stop();
    check(code === 0, `Ctrl-C stops the server cleanly (exit code ${code})`);
    fs.rmSync(dir, { recursive: true, force: true });
  }
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
