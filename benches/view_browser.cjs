// `filmsplat view` measured in headless chromium, as a user drives it: the bubble of
// samples/bubble.toml at N particles (default 1 000 000) as disks in a 960x540 window;
// orbit by dragging for 5 s and count the pictures shown (240x135 move pass), let go and time
// the first refined picture and the final one. Prints the machine's load beside each number.
//   bash tests/browser/run.sh benches/view_browser.cjs [PARTICLES...]
'use strict';

const fs = require('fs');
const os = require('os');
const path = require('path');
const h = require('../tests/browser/harness.cjs');

const load = () => os.loadavg().map((l) => l.toFixed(2)).join(', ');

async function bench(particles) {
  const dir = h.tempDir('browser-bench');
  const scene = path.join(dir, 'bubble.toml');
  const text = fs.readFileSync(path.join(__dirname, '..', 'samples', 'bubble.toml'), 'utf8');
  fs.writeFileSync(scene, text.replace('particles = 200000', `particles = ${particles}`));
  const viewer = await h.startViewer([scene]);
  const browser = await h.launch({ width: 960, height: 540 });
  const { page } = browser;
  try {
    await page.goto(viewer.url);
    await h.waitFinal(page);
    const before = await page.evaluate(() => window.filmsplat.shown.moves);
    await page.mouse.move(600, 300);
    await page.mouse.down();
    const t0 = Date.now();
    let x = 600;
    let dir = 1;
    while (Date.now() - t0 < 5000) {
      x += 4 * dir;
      if (x > 900 || x < 400) dir = -dir;
      await page.mouse.move(x, 300);
      await page.waitForTimeout(16);
    }
    const seconds = (Date.now() - t0) / 1000;
    const moves = (await page.evaluate(() => window.filmsplat.shown.moves)) - before;
    await page.mouse.up();
    console.log(`${particles} particles, 960x540 window: orbiting ${(moves / seconds).toFixed(1)} pictures/s (240x135 move pass) (load ${load()})`);
    await page.waitForFunction(() => {
      const s = window.filmsplat.shown;
      return s.log.some((e) => e.pass === 'final' && e.at > s.releasedAt);
    }, null, { timeout: h.LONG });
    const { draft, fin } = await page.evaluate(() => {
      const s = window.filmsplat.shown;
      const after = (p) => s.log.find((e) => e.pass === p && e.at > s.releasedAt);
      return { draft: after('draft').at - s.releasedAt, fin: after('final').at - s.releasedAt };
    });
    console.log(`  let go: first refined picture after ${(draft / 1000).toFixed(2)} s, final after ${(fin / 1000).toFixed(2)} s (load ${load()})`);
  } finally {
    await browser.close();
    await viewer.stop();
    fs.rmSync(dir, { recursive: true, force: true });
  }
}

(async () => {
  const counts = process.argv.slice(2).map(Number).filter((n) => n > 0);
  for (const n of counts.length ? counts : [1000000, 100000]) await bench(n);
})().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
