// How long a viewer takes to open and to draw one still frame, in headless
// Chromium, for each of several page settings (URL queries): the time from
// the start of the page's loading to its first frame, and the median and
// 90th percentile of `trephineViewer.render()` (one render of the 3D view,
// finished with a pixel read so the GPU's work is counted) over 30 renders.
// For tools/bench_viewer.py --views.
//   node viewerFrameTimes.mjs --web plugins/viewer/web --view DIR --queries 'a=1|b=2' --out FILE
import { createRequire } from 'node:module';
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const options = {};
for (let i = 2; i < process.argv.length; i += 2) options[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const { chromium } = createRequire(path.resolve(options.web, 'package.json'))('playwright-core');
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
         '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const rows = [];
try {
  for (const query of options.queries.split('|')) {
    const page = await browser.newPage({ viewport: { width: 1000, height: 760 } });
    await page.goto(`${pathToFileURL(path.resolve(options.view, 'index.html')).href}?${query}`);
    await page.waitForFunction(() => {
      const v = window.trephineViewer;
      return v && v.ready && Object.values(v.levels || {}).every((l) => l === 'still') &&
             (!/ct=1/.test(window.location.search) || (v.ct && v.ct.shown));
    }, null, { timeout: 120000 });
    const times = await page.evaluate(() => new Promise((done) => {
      const v = window.trephineViewer;
      // Every 3D view's context (runs side by side have one each).
      const contexts = [...document.querySelectorAll('#view canvas')].map((c) => c.getContext('webgl2')).filter(Boolean);
      const pixel = new Uint8Array(4);
      const out = [];
      for (let i = 0; i < 30; ++i) {
        const start = performance.now();
        v.render();
        for (const gl of contexts) gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);  // waits for the frame
        out.push(performance.now() - start);
      }
      done(out);
    }));
    times.sort((a, b) => a - b);
    const openSeconds = await page.evaluate(() => window.trephineViewer.openSeconds);
    rows.push({ query, openSeconds, renderMedianMs: times[15], renderP90Ms: times[27] });
    console.log(JSON.stringify(rows[rows.length - 1]));
    await page.close();
  }
} finally {
  await browser.close();
}
writeFileSync(options.out, JSON.stringify(rows, null, 2));
