// What a person checks in a run's viewer, in headless Chromium, on the
// default scene (trephine view of a run of it):
//   - colour maps: the brain is coloured by displacement at opening, with a
//     legend whose range is the run's largest displacement; at the deepest
//     press on the brain, the surface around the probe is in the warm half
//     of the map and the brain far from it in the cold half (the dent is
//     seen); each mode's legend says what it shows, hidden with its part;
//   - orientation: the triad shows +z up at opening, looks down z from
//     superior with anterior up, shows the patient's left on the right from
//     anterior, and comes back with reset; the scale bar halves its mm per
//     pixel when the view is zoomed twice; the wheel zooms toward the
//     cursor (the point under it stays); hiding the skull keeps the camera;
//     a clipping plane reveals the brain inside the opaque skull;
//   - the CT as a volume: drawn over much of the view, and the drilled
//     region in orange where the drill cut by the time shown, none before;
//   - plots and events: every event of the run's summary has a mark on the
//     time slider at its time, a click on it goes there, and the plots draw
//     it in its kind's colour; the read-out under the cursor gives the
//     plotted values at its time.
// Screenshots and results.json go to --out.
//   node viewerControlsTest.mjs --web plugins/viewer/web --view RUN/view --out DIR --press T
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { classify } from './pixels.mjs';
import { decodePng } from './png.mjs';
import { checker, consoleErrorsOf, finish, launchChromium, parseOptions } from './browserSupport.mjs';

const options = parseOptions('viewerControlsTest', ['web', 'view', 'out', 'press']);
mkdirSync(options.out, { recursive: true });
const { check, failures } = checker();

// Hue (degrees) and saturation of an RGB pixel.
function hueOf(r, g, b) {
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  if (max === min) return { hue: NaN, saturation: 0 };
  const d = max - min;
  let h = max === r ? ((g - b) / d) % 6 : max === g ? (b - r) / d + 2 : (r - g) / d + 4;
  h *= 60;
  if (h < 0) h += 360;
  return { hue: h, saturation: d / max };
}

const browser = await launchChromium(options.web);
const results = {};
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 820 } });
  const consoleErrors = consoleErrorsOf(page);
  const url = pathToFileURL(path.resolve(options.view, 'index.html')).href;
  const frames = () => page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  const open = async (query) => {
    await page.goto(`${url}?${query}`);
    await page.waitForFunction(() => {
      const v = window.trephineViewer;
      return v && v.ready && Object.values(v.levels || {}).every((l) => l === 'still');
    }, null, { timeout: 60000 });
    await frames();
    await frames();
  };
  const status = (what) => page.evaluate((w) => {
    const v = window.trephineViewer;
    return JSON.parse(JSON.stringify(w === 'tool' ? v.toolOnScreen() : w === 'camera' ? v.camera() : v[w]));
  }, what);
  const shoot = async (name) => {
    const png = await page.locator('#view').screenshot();
    writeFileSync(path.join(options.out, name), png);
    return decodePng(png);
  };
  const toggle = async (part, on) => {
    const box = page.locator('#parts label', { hasText: new RegExp(`^ ?${part}$`) }).locator('input');
    if ((await box.isChecked()) !== on) await box.click();
    await frames();
  };
  const manifest = async () => page.evaluate(() => window.trephineRun);

  // Colour maps: the dent, at the deepest press, the skull and the tool hidden.
  const press = Number(options.press);
  await open(`t=${press}&hide=skull`);
  const run = await manifest();
  const brainPart = run.parts.find((p) => p.kind === 'mesh');
  let legends = await status('legends');
  check(legends.brain && /displacement/.test(legends.brain.title) && legends.brain.min === 0 &&
        Math.abs(legends.brain.max - brainPart.ranges.displacement) < 1e-9,
        `the brain opens coloured by displacement, its legend 0 to ${legends.brain && legends.brain.max} mm (the run's largest: ${brainPart.ranges.displacement})`);
  check(await page.locator('.legend-entry[data-part=brain] .legend-title').innerText().then((t) => /\(mm\)/.test(t)),
        'the legend names its unit');
  const tool = await status('tool');
  await toggle('tool', false);
  await toggle('toolshape', false);
  const dent = await shoot('dent_displacement.png');
  const near = { warm: 0, all: 0 };
  const far = { warm: 0, all: 0 };
  for (let y = 0; y < dent.height; ++y) {
    for (let x = 0; x < dent.width; ++x) {
      const o = 4 * (y * dent.width + x);
      const { hue, saturation } = hueOf(dent.pixels[o], dent.pixels[o + 1], dent.pixels[o + 2]);
      if (saturation < 0.35 || Math.max(dent.pixels[o], dent.pixels[o + 1], dent.pixels[o + 2]) < 50) continue;  // background, legend text
      if (x > dent.width - 260 && y < 300) continue;  // the legend
      const distance = Math.hypot(x - tool.x, y - tool.y);
      const bin = distance < 2.5 * tool.radius ? near : distance > 10 * tool.radius ? far : null;
      if (!bin) continue;
      bin.all += 1;
      if (hue < 160) bin.warm += 1;  // green to red: the upper half of the map
    }
  }
  results.dent = { tool, near, far };
  check(near.all > 50 && near.warm / near.all > 0.5,
        `around the probe ${near.warm} of ${near.all} brain pixels are in the warm half of the map (more than half)`);
  check(far.all > 1000 && far.warm / far.all < 0.1,
        `far from it ${far.warm} of ${far.all} are (less than a tenth)`);
  // Stress, and a hidden part's legend.
  await page.selectOption('#colour-brain', 'stress');
  await frames();
  legends = await status('legends');
  check(legends.brain && /von Mises/.test(legends.brain.title) && legends.brain.max === brainPart.ranges.von_mises,
        `stress: the legend says "${legends.brain && legends.brain.title}" up to ${legends.brain && legends.brain.max} kPa`);
  await toggle('brain', false);
  legends = await status('legends');
  check(legends.brain && !legends.brain.shown && !(await page.locator('.legend-entry[data-part=brain]').isVisible()),
        'hiding the brain hides its legend');
  await toggle('brain', true);
  // The skull by where it was cut, and by density.
  const skullPart = run.parts.find((p) => p.kind === 'blocks');
  if (skullPart && skullPart.volume) {
    await page.selectOption('#colour-skull', 'cut');
    await page.waitForFunction(() => window.trephineViewer.legends.skull, null, { timeout: 30000 });
    legends = await status('legends');
    check(/cut/.test(legends.skull.title) && legends.skull.max === run.end, `the skull's cuts: legend "${legends.skull.title}" 0 to ${legends.skull.max} s`);
    await page.selectOption('#colour-skull', 'density');
    await frames();
    legends = await status('legends');
    check(/density/.test(legends.skull.title) && legends.skull.max > legends.skull.min, `density: legend ${legends.skull.min} to ${legends.skull.max}`);
  }

  // Orientation.
  await open('t=0&brain=tissue');
  let controls = await status('controls');
  const opening = controls.triad;
  check(opening['z (S)'][1] > 0.8, `at opening +z points up the screen (${opening['z (S)'].map((v) => v.toFixed(2))})`);
  await page.click('button[data-view=superior]');
  await frames();
  controls = await status('controls');
  check(Math.hypot(...controls.triad['z (S)']) < 0.05 && controls.triad['y (P)'][1] < -0.95,
        `superior: z points at the viewer, posterior down the screen (anterior up)`);
  await page.click('button[data-view=anterior]');
  await frames();
  controls = await status('controls');
  check(controls.triad['x (L)'][0] > 0.95 && controls.triad['z (S)'][1] > 0.95,
        "anterior: the patient's left on the screen's right, superior up");
  await page.click('button[data-view=reset]');
  await frames();
  controls = await status('controls');
  check(Object.keys(opening).every((k) => Math.hypot(opening[k][0] - controls.triad[k][0], opening[k][1] - controls.triad[k][1]) < 1e-6),
        'reset gives back the opening view');
  // The scale bar against the camera: zoomed twice, half the mm per pixel.
  const before = (await status('controls')).scaleBar;
  await page.evaluate(() => {
    const v = window.trephineViewer;
    v.zoomForTest(2);
  });
  await frames();
  const after = (await status('controls')).scaleBar;
  check(Math.abs(after.mmPerPixel / before.mmPerPixel - 0.5) < 0.01 && after.pixels > 40 && after.pixels < 200,
        `zoomed twice, the scale bar's mm per pixel goes from ${before.mmPerPixel.toFixed(4)} to ${after.mmPerPixel.toFixed(4)}; it is ${after.mm} mm over ${after.pixels.toFixed(0)} pixels`);
  await page.click('button[data-view=reset]');
  await frames();
  // The wheel zooms toward the cursor: the tool under it stays there.
  await open(`t=${press}&hide=skull&brain=tissue`);
  const box = await page.locator('#view').boundingBox();
  const under = await status('tool');
  const scaleBefore = (await status('controls')).scaleBar.mmPerPixel;
  await page.mouse.move(box.x + under.x, box.y + under.y);
  for (let i = 0; i < 4; ++i) {
    await page.mouse.wheel(0, -120);
    await frames();
  }
  const moved = await status('tool');
  const scaleAfter = (await status('controls')).scaleBar.mmPerPixel;
  const centre = Math.hypot(under.x - box.width / 2, under.y - box.height / 2);
  check(scaleAfter < 0.8 * scaleBefore && Math.hypot(moved.x - under.x, moved.y - under.y) < Math.max(6, 0.1 * centre),
        `the wheel zooms in (${scaleBefore.toFixed(3)} to ${scaleAfter.toFixed(3)} mm per pixel) and the probe under the cursor moves ${Math.hypot(moved.x - under.x, moved.y - under.y).toFixed(1)} pixels (it is ${centre.toFixed(0)} from the centre)`);
  // Hiding the skull keeps the camera.
  await open('t=1');
  const cameraBefore = await status('camera');
  await toggle('skull', false);
  await toggle('skull', true);
  const cameraAfter = await status('camera');
  check(JSON.stringify(cameraBefore) === JSON.stringify(cameraAfter), 'hiding and showing the skull keeps the camera');
  // A clipping plane reveals the brain inside the opaque skull.
  await open(`t=${press}&brain=tissue&hide=tool,toolshape`);
  const closed = classify(await shoot('clip_off.png'));
  await page.selectOption('#clip-axis', '1');
  await frames();
  const clipped = classify(await shoot('clip_y.png'));
  const area = closed.labels.length;
  check(closed.brain.count < 0.002 * area && clipped.brain.count > 0.02 * area,
        `clipping front-back at half the depth shows the brain: ${closed.brain.count} brain pixels before, ${clipped.brain.count} after`);

  // The CT volume, from above, everything else hidden: orange (the cut
  // colour) only once the drill has cut, where it cut.
  if (skullPart && skullPart.volume) {
    const orange = (image) => {
      let n = 0;
      let lit = 0;
      for (let i = 0; i < image.pixels.length; i += 4) {
        const { hue, saturation } = hueOf(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]);
        if (Math.max(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]) > 70) ++lit;
        if (saturation > 0.5 && hue > 15 && hue < 42 && image.pixels[i] > 120) ++n;
      }
      return { orange: n, lit };
    };
    const counts = [];
    for (const t of [0, press]) {
      await open(`t=${t}&ct=1&hide=skull,brain,tool,toolshape&view=superior`);
      await page.waitForFunction(() => window.trephineViewer.ct && window.trephineViewer.ct.shown, null, { timeout: 30000 });
      await frames();
      const image = await shoot(`ct_t${t}.png`);
      counts.push({ t, ...orange(image), area: image.width * image.height, cut: (await status('ct')).cutVoxels });
    }
    results.ct = counts;
    check(counts[0].lit > 0.1 * counts[0].area, `the CT volume is drawn on ${counts[0].lit} pixels (a tenth of the view at least)`);
    // (The craniotomy's first burr hole is small: 48 packed voxels, some 75 pixels at this zoom.)
    check(counts[0].cut === 0 && counts[0].orange < 20 && counts[1].cut > 0 && counts[1].orange > Math.max(30, 10 * (counts[0].orange + 1)),
          `the drilled region: ${counts[0].orange} orange pixels at 0 s (no voxel cut), ${counts[1].orange} at ${press} s (${counts[1].cut} voxels cut)`);
  }

  // Events on the time slider and the plots.
  await open('t=0');
  const events = await status('events');
  results.events = events;
  const marks = await page.locator('#marks .mark').evaluateAll((nodes) => nodes.map((n) => {
    const b = n.getBoundingClientRect();
    return { t: Number(n.dataset.t), kind: n.dataset.kind, x: b.left + b.width / 2 };
  }));
  const track = await page.locator('#marks').boundingBox();
  check(events.length > 0 && marks.length === events.length, `${marks.length} marks on the time slider for the run's ${events.length} events`);
  check(marks.every((m, i) => m.t === events[i].t && Math.abs(m.x - (track.x + (track.width * m.t) / run.end)) < 2),
        'each mark sits at its event\'s time along the slider');
  if (marks.length) {
    const last = marks.length - 1;
    await page.locator('#marks .mark').nth(last).click();
    const time = await status('time');
    check(Math.abs(time - events[last].t) < 1e-9, `a click on the ${events[last].kind} mark goes to ${time} s (${events[last].t} s)`);
    const plotsBox = await page.locator('#plots').boundingBox();
    const png = decodePng(await page.locator('#plots').screenshot());
    const colours = await page.evaluate(() => window.trephineViewer.plots.colours);
    const want = colours[events[0].kind].match(/[0-9a-f]{2}/gi).map((h) => parseInt(h, 16));
    const x = Math.round(await page.evaluate((t) => window.trephineViewer.plots.clientXOf(t), events[0].t) - plotsBox.x);
    let found = 0;
    for (let y = 0; y < png.height; ++y) {
      for (const dx of [-1, 0, 1]) {
        const o = 4 * (y * png.width + x + dx);
        if (Math.abs(png.pixels[o] - want[0]) + Math.abs(png.pixels[o + 1] - want[1]) + Math.abs(png.pixels[o + 2] - want[2]) < 60) { ++found; break; }
      }
    }
    check(found > 0.4 * png.height, `the plots mark the ${events[0].kind} at ${events[0].t} s in its colour (${found} of ${png.height} rows)`);
    // The read-out at the cursor.
    const t = run.end * 0.37;
    await page.mouse.move(await page.evaluate((tt) => window.trephineViewer.plots.clientXOf(tt), t), plotsBox.y + plotsBox.height / 2);
    const readout = await page.evaluate(() => window.trephineViewer.plots.readout);
    const expected = await page.evaluate((tt) => {
      const p = window.trephineRun.plots;
      let i = 0;
      while (i + 1 < p.t.length && p.t[i + 1] <= tt) ++i;
      return { force: p.force[i], penetration: p.penetration[i] };
    }, readout.t);
    check(Math.abs(readout.t - t) < run.end / 500 && readout.force === expected.force && readout.penetration === expected.penetration,
          `the read-out at ${t.toFixed(3)} s says t ${readout.t.toFixed(3)} s, |F| ${readout.force.toPrecision(3)} N, penetration ${readout.penetration.toPrecision(3)} mm (the plotted values)`);
    // Every tool is plotted and named: a second tool's trace (as a run with
    // two tools gives, trace.PATH.csv) dashed beside trace.csv's, named in the
    // key and in the read-out by its renderer's path.
    const plotsCanvas = page.locator('#plots');
    const before = await plotsCanvas.screenshot();
    const tool = await page.evaluate((end) => {
      const p = window.trephineViewer.plots;
      const n = 200;
      const ts = Array.from({ length: n }, (_, i) => (i * end) / (n - 1));
      p.setTools([{ name: '/second/force', t: ts, force: ts.map((x) => 3 * Math.sin(x) ** 2), penetration: ts.map(() => 1.25) }]);
      const at = end * 0.5;
      const values = p.valuesAt(at);
      return { line: p.readoutLine(at, values), penetration: values.penetration_tool0 };
    }, run.end);
    const after = await plotsCanvas.screenshot();
    check(tool.penetration === 1.25 && tool.line.includes('/second/force: ') && tool.line.includes('1.25 mm'),
          `the read-out names the second tool and gives its values: "${tool.line}"`);
    check(!before.equals(after), 'the second tool is drawn in the plots (the canvas changes)');
    await page.evaluate(() => window.trephineViewer.plots.setTools([]));
  }
  // URL parameters the page cannot follow are said, and it opens as by default.
  await page.goto(`${pathToFileURL(path.resolve(options.view, 'index.html')).href}?t=abc&brain=bogus&view=nonsense&speed=-2`);
  await page.waitForFunction(() => window.trephineViewer && window.trephineViewer.ready, null, { timeout: 60000 });
  const warnings = await page.evaluate(() => window.trephineViewer.warnings || []);
  const message = await page.locator('#message').innerText();
  check(['t=abc', 'brain=bogus', 'view=nonsense', 'speed=-2'].every((w) => warnings.some((x) => x.startsWith(w)) && message.includes(w)) &&
        (await status('time')) === 0,
        `bad parameters are said on the page (${warnings.length}: ${warnings.map((w) => w.split(':')[0]).join(', ')}) and it opens at 0 s`);
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await browser.close();
}
finish(options.out, results, failures);
