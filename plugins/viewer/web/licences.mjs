// Writes the licences of the npm packages an esbuild bundle holds: reads the
// bundle's metafile (esbuild --metafile), finds each package its inputs come
// from, and writes its name, version, licence and licence text.
//   node licences.mjs META.json OUT.txt
import { readFileSync, existsSync, readdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';

const [metafile, out] = process.argv.slice(2);
const inputs = Object.keys(JSON.parse(readFileSync(metafile, 'utf8')).inputs);
const packages = new Set();
for (const input of inputs) {
  const match = input.match(/node_modules\/((?:@[^/]+\/)?[^/]+)\//);
  if (match) packages.add(match[1]);
}
let text = 'The viewer (viewer.js) bundles parts of these packages, under these licences.\n';
for (const name of [...packages].sort()) {
  const dir = path.join('node_modules', name);
  const manifest = JSON.parse(readFileSync(path.join(dir, 'package.json'), 'utf8'));
  text += `\n${'='.repeat(78)}\n${name} ${manifest.version}: ${manifest.license || 'see below'}\n${'='.repeat(78)}\n`;
  const licence = readdirSync(dir).find((f) => /^(licen[cs]e|copying)(\..*)?$/i.test(f));
  text += licence && existsSync(path.join(dir, licence)) ? readFileSync(path.join(dir, licence), 'utf8')
                                                         : '(no licence file in the package)\n';
}
writeFileSync(out, text);
