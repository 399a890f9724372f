// Runs side by side (trephine view RUN_A RUN_B --out DIR) in headless
// Chromium: both runs drawn, each in its own view, at one time; turning one
// view turns the other (linked cameras); the brain coloured on one range,
// the larger of the two runs'; the plots carry both runs' |F| in their
// colours and a row of their difference, whose read-out is run 1's |F| less
// run 0's at the cursor's time; a stiffer brain (run 1) dents less.
//   node viewerCompareTest.mjs --web plugins/viewer/web --view DIR --out DIR --press T
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { classify } from './pixels.mjs';
import { decodePng } from './png.mjs';
import { checker, consoleErrorsOf, finish, launchChromium, parseOptions } from './browserSupport.mjs';

const options = parseOptions('viewerCompareTest', ['web', 'view', 'out', 'press']);
mkdirSync(options.out, { recursive: true });
const { check, failures } = checker();
const browser = await launchChromium(options.web);
const results = {};
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  const consoleErrors = consoleErrorsOf(page);
  const press = Number(options.press);
  await page.goto(`${pathToFileURL(path.resolve(options.view, 'index.html')).href}?t=${press}&hide=skull,tool,toolshape&brain=tissue`);
  await page.waitForFunction(() => window.trephineViewer && window.trephineViewer.ready, null, { timeout: 60000 });
  await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  const runs = await page.evaluate(() => window.trephineRuns.map((m) => ({ name: m.name, end: m.end, frames: m.frames.length, ranges: m.parts.find((p) => p.kind === 'mesh').ranges })));
  const state = await page.evaluate(() => JSON.parse(JSON.stringify({ runs: window.trephineViewer.runs, time: window.trephineViewer.time })));
  check(runs.length === 2 && (await page.locator('.run-view').count()) === 2, `two runs, two views (${runs.map((r) => r.name).join(', ')})`);
  // Each view's canvas fills its pane, the two alike (one camera: one picture size).
  const boxes = await page.evaluate(() => [...document.querySelectorAll('.run-view')].map((pane) => {
    const p = pane.getBoundingClientRect();
    const c = pane.querySelector('canvas').getBoundingClientRect();
    return { paneWidth: p.width, paneHeight: p.height, width: c.width, height: c.height };
  }));
  check(boxes.every((b) => Math.abs(b.width - b.paneWidth) < 3 && Math.abs(b.height - b.paneHeight) < 3) &&
        Math.abs(boxes[0].height - boxes[1].height) < 2,
        `each canvas fills its pane (${boxes.map((b) => `${b.width.toFixed(0)}x${b.height.toFixed(0)} in ${b.paneWidth.toFixed(0)}x${b.paneHeight.toFixed(0)}`).join(', ')})`);
  const frameAt = (k) => page.evaluate(([k, t]) => {
    const frames = window.trephineRuns[k].frames;
    let i = 0;
    while (i + 1 < frames.length && frames[i + 1].t <= t + 1e-9) ++i;
    return i;
  }, [k, press]);
  check(state.runs[0].frame === await frameAt(0) && state.runs[1].frame === await frameAt(1),
        `both show the frame of ${press} s (${state.runs[0].frame}, ${state.runs[1].frame})`);
  for (let k = 0; k < 2; ++k) {
    const png = decodePng(await page.locator(`.run-view[data-run="${k}"]`).screenshot());
    writeFileSync(path.join(options.out, `run_${k}.png`), await page.locator(`.run-view[data-run="${k}"]`).screenshot());
    const found = classify(png);
    check(found.brain.count > 0.05 * png.width * png.height, `run ${k}'s view draws its brain on ${found.brain.count} pixels`);
  }
  // Linked cameras: a drag in the second view turns the first.
  const before = await page.evaluate(() => window.trephineViewer.cameras());
  const second = await page.locator('.run-view[data-run="1"]').boundingBox();
  await page.mouse.move(second.x + second.width / 2, second.y + second.height / 2);
  await page.mouse.down();
  await page.mouse.move(second.x + second.width / 2 + 120, second.y + second.height / 2 + 40, { steps: 8 });
  await page.mouse.up();
  const after = await page.evaluate(() => window.trephineViewer.cameras());
  const turned = Math.hypot(...after[1].position.map((v, a) => v - before[1].position[a]));
  const apart = Math.hypot(...after[0].position.map((v, a) => v - after[1].position[a]));
  check(turned > 1 && apart < 1e-6, `a drag in run 1's view moved its camera ${turned.toFixed(1)} mm, and run 0's camera is ${apart} mm from it`);
  // One colour range: the larger of the two runs' displacements.
  await page.selectOption('#colour-brain', 'displacement');
  const legend = await page.evaluate(() => window.trephineViewer.legends.brain);
  const largest = Math.max(runs[0].ranges.displacement, runs[1].ranges.displacement);
  check(legend && legend.max === largest, `the legend spans 0 to ${legend && legend.max} mm, the larger run's (${largest})`);
  check(runs[1].ranges.displacement < runs[0].ranges.displacement,
        `the stiffer brain (run 1) dents less: ${runs[1].ranges.displacement.toFixed(2)} mm against ${runs[0].ranges.displacement.toFixed(2)} mm`);
  // The plots: the difference read out at the cursor.
  const plotsBox = await page.locator('#plots').boundingBox();
  const t = press;
  await page.mouse.move(await page.evaluate((tt) => window.trephineViewer.plots.clientXOf(tt), t), plotsBox.y + plotsBox.height / 2);
  const readout = await page.evaluate(() => window.trephineViewer.plots.readout);
  const expected = await page.evaluate((tt) => {
    const at = (p) => {
      let i = 0;
      while (i + 1 < p.t.length && p.t[i + 1] <= tt) ++i;
      return p.force[i];
    };
    return { f0: at(window.trephineRuns[0].plots), f1: at(window.trephineRuns[1].plots) };
  }, readout.t);
  check(readout.force_0 === expected.f0 && readout.force_1 === expected.f1 && Math.abs(readout.difference_1 - (expected.f1 - expected.f0)) < 1e-12,
        `at ${readout.t.toFixed(3)} s the read-out gives |F| ${expected.f0.toFixed(3)} and ${expected.f1.toFixed(3)} N, difference ${readout.difference_1.toFixed(3)} N`);
  const png = decodePng(await page.locator('#plots').screenshot());
  writeFileSync(path.join(options.out, 'plots.png'), await page.locator('#plots').screenshot());
  const colourCount = (hex) => {
    const want = hex.match(/[0-9a-f]{2}/gi).map((h) => parseInt(h, 16));
    let n = 0;
    for (let i = 0; i < png.pixels.length; i += 4)
      n += Math.abs(png.pixels[i] - want[0]) + Math.abs(png.pixels[i + 1] - want[1]) + Math.abs(png.pixels[i + 2] - want[2]) < 40;
    return n;
  };
  const colours = ['#f2553a', '#4f8ff5'].map(colourCount);
  check(colours[0] > 200 && colours[1] > 200, `the plots draw run 0's curves (${colours[0]} pixels) and run 1's (${colours[1]}) in their colours`);
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await browser.close();
}
finish(options.out, results, failures);
