// What the browser tests share: their options, their checks, and headless
// Chromium with software WebGL.
import { createRequire } from 'node:module';
import { writeFileSync } from 'node:fs';
import path from 'node:path';

// --name value pairs; exits (2) naming the first of `required` missing.
export function parseOptions(program, required) {
  const options = {};
  for (let i = 2; i < process.argv.length; i += 2) options[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
  for (const name of required) {
    if (!options[name]) {
      console.error(`${program}: --${name} is missing`);
      process.exit(2);
    }
  }
  return options;
}

// check(ok, message) prints each check; failures lists those that failed.
export function checker() {
  const failures = [];
  const check = (ok, message) => {
    if (!ok) failures.push(message);
    console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
  };
  return { check, failures };
}

// Debian's Chromium (or $CHROMIUM), headless, WebGL in SwiftShader.
export function launchChromium(web) {
  const { chromium } = createRequire(path.resolve(web, 'package.json'))('playwright-core');
  return chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
           '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
           '--disable-quic'],
  });
}

// The page's console errors and uncaught exceptions, as they come.
export function consoleErrorsOf(page) {
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  return errors;
}

// Writes `results` (with the failures) to OUT/results.json and exits: 1
// when a check failed.
export function finish(out, results, failures) {
  results.failures = failures;
  writeFileSync(path.join(out, 'results.json'), JSON.stringify(results, null, 2));
  process.exit(failures.length ? 1 : 0);
}
