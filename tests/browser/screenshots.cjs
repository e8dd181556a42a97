// The README's screenshots of `filmsplat view`: samples/bubble.toml in a 960x540 window, the
// shaded view after an orbit, and the thickness view with the shortcut list open.
//   bash tests/browser/run.sh tests/browser/screenshots.cjs
'use strict';

const path = require('path');
const h = require('./harness.cjs');

const OUT = path.join(__dirname, '..', '..', 'samples', 'images');

(async () => {
  // Run from the checkout's root (run.sh is), so the page names the scene as a user types it.
  const viewer = await h.startViewer(['samples/bubble.toml']);
  const browser = await h.launch({ width: 960, height: 540 });
  const { page } = browser;
  try {
    await page.goto(viewer.url);
    let shown = await h.waitFinal(page);
    await h.drag(page, [600, 300], [540, 320]);
    shown = await h.waitFinal(page, Number(shown.version));
    await h.drag(page, [600, 300], [690, 300], true);
    shown = await h.waitFinal(page, Number(shown.version));
    await page.screenshot({ path: path.join(OUT, 'view_shaded.png') });
    await page.selectOption('#view', 'thickness');
    shown = await h.waitFinal(page, Number(shown.version), { view: 'thickness' });
    await page.mouse.click(480, 500);
    await page.keyboard.press('?');
    await page.screenshot({ path: path.join(OUT, 'view_thickness.png') });
    console.log(`wrote ${OUT}/view_shaded.png and view_thickness.png`);
  } finally {
    await browser.close();
    await viewer.stop();
  }
})().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
