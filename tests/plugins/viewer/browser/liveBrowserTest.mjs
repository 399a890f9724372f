// The live view end to end: starts `trephine run SCENE --realtime --view 0`,
// opens the address it prints in headless Chromium while the run goes, and
// checks that the viewer draws the parts named (the brain's with the skull
// hidden), that two screenshots some seconds apart differ where the tool
// moved, that frames keep coming, that there is no console error, and that
// the run ends well. Screenshots and live.json go to --out.
//   node liveBrowserTest.mjs --web plugins/viewer/web --trephine build/bin/trephine --scene S --duration D
//        --times T1,T2 --parts skull,brain,tool --out DIR
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { classify, differenceNearTool } from './pixels.mjs';
import { decodePng } from './png.mjs';

const options = {};
for (let i = 2; i < process.argv.length; i += 2) options[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const { chromium } = createRequire(path.resolve(options.web, 'package.json'))('playwright-core');
const times = options.times.split(',').map(Number);
const parts = options.parts.split(',');
mkdirSync(options.out, { recursive: true });
const failures = [];
const check = (ok, message) => {
  if (!ok) failures.push(message);
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
};

const run = spawn(options.trephine, ['run', options.scene, '--realtime', '--view', '0', '--duration', options.duration,
                                     '--out', path.join(options.out, 'run'), '--quiet'], { stdio: ['ignore', 'pipe', 'pipe'] });
let output = '';
run.stdout.on('data', (d) => { output += d; });
run.stderr.on('data', (d) => { output += d; });
const exited = new Promise((done) => run.on('exit', (code) => done(code)));
const address = await new Promise((done, fail) => {
  const timer = setInterval(() => {
    const found = output.match(/view\s+(http:\/\/127\.0\.0\.1:\d+\/)/);
    if (found) {
      clearInterval(timer);
      done(found[1]);
    }
  }, 50);
  exited.then((code) => fail(new Error(`the run ended (${code}) before serving: ${output}`)));
});

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
         '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const results = { address, screenshots: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 760 } });
  const consoleErrors = [];
  page.on('console', (message) => { if (message.type() === 'error') consoleErrors.push(message.text()); });
  page.on('pageerror', (error) => consoleErrors.push(String(error)));
  await page.goto(address);
  await page.waitForFunction(() => window.trephineViewer && window.trephineViewer.ready, null, { timeout: 30000 });
  const state = () => page.evaluate(() => ({ ...window.trephineViewer }));
  let s = await state();
  results.openSeconds = s.openSeconds;
  results.renderer = s.renderer;
  check(s.openSeconds < 5, `the live view draws its first frame ${s.openSeconds.toFixed(2)} s after loading`);
  for (const part of parts.filter((p) => p !== 'tool'))
    check(s.triangles[part] > 0, `${part}: ${s.triangles[part]} triangles drawn`);
  const view = page.locator('#view');
  const shots = [];
  for (const [i, t] of times.entries()) {
    await page.waitForFunction((time) => window.trephineViewer.time >= time, t, { timeout: 60000 });
    // Hold still for the shots: the brain and tool as they were at t.
    await page.evaluate(() => { window.trephineViewer.frozen = true; });
    const before = await state();
    const toggle = async (on) => {
      const box = page.locator('#parts label', { hasText: /^ ?skull$/ }).locator('input');
      if ((await box.isChecked()) !== on) await box.click();
    };
    let all = null;
    if (parts.includes('skull')) {
      const png = await view.screenshot();
      writeFileSync(path.join(options.out, `live_t${i}.png`), png);
      all = decodePng(png);
      const found = classify(all);
      check(found.skull.count >= 0.01 * all.width * all.height, `t = ${before.time.toFixed(2)} s: skull drawn on ${found.skull.count} pixels`);
      await toggle(false);
    }
    const png = await view.screenshot();
    writeFileSync(path.join(options.out, `live_t${i}_inside.png`), png);
    if (parts.includes('skull')) await toggle(true);
    const image = decodePng(png);
    const found = classify(image);
    shots.push({ image, found, time: before.time });
    if (parts.includes('brain'))
      check(found.brain.count >= 0.01 * image.width * image.height, `t = ${before.time.toFixed(2)} s: brain drawn on ${found.brain.count} pixels`);
    check(found.proxy.count >= 20, `t = ${before.time.toFixed(2)} s: proxy drawn on ${found.proxy.count} pixels`);
    await page.evaluate(() => { window.trephineViewer.frozen = false; });
    if (i === 0) {
      // Frames keep coming: those drawn in two seconds of the run. The
      // floor (4 a second) catches a stream that stalls; the rate itself
      // depends on the guest, where the browser shares two cores with the
      // simulation's four groups (14 a second on one, 7 to 14 on a slower
      // one: docs/results.md).
      const a = await state();
      await page.waitForTimeout(2000);
      const b = await state();
      results.framesPerSecond = (b.framesDrawn - a.framesDrawn) / 2;
      results.simulatedPerSecond = (b.time - a.time) / 2;
      check(results.framesPerSecond >= 4,
            `${results.framesPerSecond.toFixed(1)} frames drawn a second while ${results.simulatedPerSecond.toFixed(2)} s of the run went by each second (at least 4)`);
    }
  }
  const difference = differenceNearTool(shots[0], shots[1]);
  results.difference = difference;
  check(difference.moved > 3, `the proxy moved ${difference.moved.toFixed(1)} pixels between ${shots[0].time.toFixed(2)} and ${shots[1].time.toFixed(2)} s`);
  check(difference.proxyChanged > 0.8,
        `${(100 * difference.proxyChanged).toFixed(0)}% of the proxy's pixels at either time changed (at least 80%); ` +
        `${difference.changed} pixels changed in all, ${(100 * difference.near).toFixed(0)}% of them around the tool`);
  results.consoleErrors = consoleErrors;
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await browser.close();
}
const code = await exited;
check(code === 0, `the run ended with ${code}${code ? ': ' + output : ''}`);
results.failures = failures;
writeFileSync(path.join(options.out, 'live.json'), JSON.stringify(results, null, 2));
process.exit(failures.length ? 1 : 0);
