// Loads a run's viewer (trephine view) in headless Chromium and checks what
// it draws:
//   - it opens (the first frame drawn) within --open-limit seconds, with no
//     console error;
//   - at two times, the parts named by --parts are drawn in their colours in
//     the 3D view (the brain's near its middle), and the two screenshots
//     differ where the tool moved;
//   - a click on the plots goes to the time under the click;
//   - playing at real time, it draws the run's frames at --min-fps or more.
// Screenshots and results.json go to --out for a person to look at.
//   node viewerBrowserTest.mjs --web plugins/viewer/web --view RUN/view --out DIR
//        --times T1,T2 --parts brain,tool[,skull] [--open-limit S] [--min-fps F]
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { classify, differenceNearTool } from './pixels.mjs';
import { decodePng } from './png.mjs';
import { checker, consoleErrorsOf, finish, launchChromium, parseOptions } from './browserSupport.mjs';

const options = parseOptions('viewerBrowserTest', ['web', 'view', 'out', 'times', 'parts']);
const times = options.times.split(',').map(Number);
const parts = options.parts.split(',');
const openLimit = Number(options['open-limit'] || 3);
const minFps = Number(options['min-fps'] || 0);
mkdirSync(options.out, { recursive: true });

const { check, failures } = checker();

const browser = await launchChromium(options.web);
const results = { times, screenshots: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 760 } });
  const consoleErrors = consoleErrorsOf(page);
  const url = pathToFileURL(path.resolve(options.view, 'index.html')).href;
  const viewer = () => page.evaluate(() => {
    const s = window.trephineViewer;
    return s && { ready: s.ready, openSeconds: s.openSeconds, time: s.time, frame: s.frame, framesDrawn: s.framesDrawn,
                  triangles: s.triangles, errors: s.errors, renderer: s.renderer };
  });
  const settle = async (frame, still = true) => {
    // The frame, with its blocks (a skull) at their still level.
    await page.waitForFunction(([f, still]) => {
      const v = window.trephineViewer;
      return v && v.ready && (f < 0 || v.frame === f) &&
             (!still || Object.values(v.levels || {}).every((l) => l === 'still'));
    }, [frame, still], { timeout: 60000 });
    // Two animation frames: the render reaches the canvas.
    await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  };

  // Opening, at the first time.
  // The brain in its tissue colour, which the pixel checks look for (the
  // colour maps: viewerControlsTest.mjs).
  await page.goto(`${url}?t=${times[0]}&brain=tissue`);
  await settle(-1);
  let state = await viewer();
  results.openSeconds = state.openSeconds;
  results.renderer = state.renderer;
  results.triangles = state.triangles;
  check(state.openSeconds < openLimit, `opens in ${state.openSeconds.toFixed(2)} s (limit ${openLimit} s) with ${state.renderer}`);
  for (const part of parts.filter((p) => p !== 'tool'))
    check(state.triangles[part] > 0, `${part}: ${state.triangles[part]} triangles drawn`);

  const view = page.locator('#view');
  const toggle = async (part, on) => {
    const box = page.locator('#parts label', { hasText: new RegExp(`^ ?${part}$`) }).locator('input');
    if ((await box.isChecked()) !== on) await box.click();
    await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  };
  const shoot = async (name) => {
    const png = await view.screenshot();
    const file = path.join(options.out, name);
    writeFileSync(file, png);
    results.screenshots.push(file);
    const image = decodePng(png);
    return { image, found: classify(image), area: image.width * image.height };
  };
  // The skull hides what is inside it: each time is shot with every part,
  // then with the skull's checkbox off.
  const shots = [];
  for (const [i, t] of times.entries()) {
    const frame = await page.evaluate((time) => {
      window.trephineViewer.seek(time);
      const frames = window.trephineRun.frames;
      let k = 0;
      while (k + 1 < frames.length && frames[k + 1].t <= time + 1e-9) ++k;
      return k;
    }, t);
    await settle(frame);
    if (parts.includes('skull')) {
      const all = await shoot(`viewer_t${i}_${t}s.png`);
      check(all.found.skull.count >= 0.01 * all.area,
            `t = ${t} s: skull drawn on ${all.found.skull.count} pixels (at least ${Math.round(0.01 * all.area)})`);
      await toggle('skull', false);
    }
    const inside = await shoot(parts.includes('skull') ? `viewer_t${i}_${t}s_no_skull.png` : `viewer_t${i}_${t}s.png`);
    if (parts.includes('skull')) await toggle('skull', true);
    shots.push(inside);
    for (const part of parts.filter((p) => p !== 'skull')) {
      const name = part === 'tool' ? 'proxy' : part;
      const least = name === 'proxy' ? 20 : 0.01 * inside.area;
      check(inside.found[name].count >= least,
            `t = ${t} s: ${name} drawn on ${inside.found[name].count} pixels (at least ${Math.round(least)})`);
    }
    if (parts.includes('brain')) {
      const b = inside.found.brain;
      const { width, height } = inside.image;
      check(Math.abs(b.x / width - 0.5) < 0.3 && Math.abs(b.y / height - 0.5) < 0.35,
            `t = ${t} s: the brain's centroid (${(b.x / width).toFixed(2)}, ${(b.y / height).toFixed(2)} of the view) near the middle`);
    }
  }
  // The two times differ where the tool moved: most changed pixels lie in
  // the box around the proxy and its force arrow at both times.
  if (shots.length === 2 && parts.includes('tool')) {
    const difference = differenceNearTool(shots[0], shots[1]);
    results.toolMovedPixels = difference.moved;
    results.changedPixels = difference.changed;
    results.changedNearTool = difference.near;
    check(difference.moved > 3, `the proxy moved ${difference.moved.toFixed(1)} pixels between the two times`);
    check(difference.proxyChanged > 0.8,
          `${(100 * difference.proxyChanged).toFixed(0)}% of the proxy's pixels at either time changed (at least 80%); ` +
          `${difference.changed} pixels changed in all, ${(100 * difference.near).toFixed(0)}% of them around the tool`);
  }

  // A click on the plots goes to its time.
  const plots = page.locator('#plots');
  const box = await plots.boundingBox();
  const target = times[times.length - 1] / 2;
  const end = await page.evaluate(() => window.trephineRun.end);
  const left = 64;
  const right = 12;
  await page.mouse.click(box.x + left + ((box.width - left - right) * target) / end, box.y + box.height / 2);
  state = await viewer();
  check(Math.abs(state.time - target) < 0.01 * end + 1e-3, `a click on the plots at ${target.toFixed(3)} s goes to ${state.time.toFixed(3)} s`);

  // Playing at real time from the start.
  if (minFps > 0) {
    await page.goto(`${url}?t=0&play=1&brain=tissue`);
    await settle(-1, false);
    const before = await viewer();
    const seconds = 3;
    const rafs = await page.evaluate((s) => new Promise((done) => {
      let n = 0;
      const start = performance.now();
      const step = (now) => {
        ++n;
        if (now - start < s * 1000) requestAnimationFrame(step);
        else done(n / ((now - start) / 1000));
      };
      requestAnimationFrame(step);
    }), seconds);
    const after = await viewer();
    const runFrames = await page.evaluate(([t0, t1]) => window.trephineRun.frames.filter((f) => f.t > t0 && f.t <= t1).length,
                                          [before.time, after.time]);
    const elapsed = after.time - before.time;  // s of the run played
    results.playFps = (after.framesDrawn - before.framesDrawn) / seconds;
    results.runFramesPerSecond = runFrames / Math.max(elapsed, 1e-9);
    results.animationFps = rafs;
    check(results.playFps >= minFps,
          `plays ${results.playFps.toFixed(1)} frames a second (the run has ${results.runFramesPerSecond.toFixed(1)}; browser animation ${rafs.toFixed(1)}/s; at least ${minFps})`);
  }
  results.consoleErrors = consoleErrors;
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await browser.close();
}
finish(options.out, results, failures);
