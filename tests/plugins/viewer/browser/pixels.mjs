// Pixel checks of the viewer's screenshots, shared by the browser tests.
// The colours the viewer draws (its scene3d.js), as chromaticities: shading
// scales a colour, so a pixel's colour over its largest channel is the
// material's whatever the light.
const kMaterials = {
  skull: [0.91, 0.87, 0.76],
  brain: [0.9, 0.55, 0.6],
  proxy: [0.2, 0.45, 0.95],
  device: [0.3, 0.85, 0.35],
  force: [0.95, 0.25, 0.15],
};
const chroma = (rgb) => {
  const top = Math.max(...rgb);
  return rgb.map((v) => v / top);
};
const kChroma = Object.fromEntries(Object.entries(kMaterials).map(([name, rgb]) => [name, chroma(rgb)]));

// Per material: its pixel count and their centroid and box; and the
// material of each pixel (labels: 0 none, else 1 + its index in kMaterials).
export function classify(image) {
  const found = {};
  const names = Object.keys(kChroma);
  found.labels = new Uint8Array(image.width * image.height);
  for (const name of Object.keys(kChroma)) found[name] = { count: 0, x: 0, y: 0, box: [Infinity, Infinity, -Infinity, -Infinity] };
  const { width, height, pixels } = image;
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const o = 4 * (y * width + x);
      const rgb = [pixels[o], pixels[o + 1], pixels[o + 2]];
      const top = Math.max(...rgb);
      if (top < 60) continue;  // background or deep shadow
      const c = rgb.map((v) => v / top);
      for (const [name, target] of Object.entries(kChroma)) {
        if (Math.hypot(c[0] - target[0], c[1] - target[1], c[2] - target[2]) > 0.07) continue;
        const f = found[name];
        found.labels[y * width + x] = 1 + names.indexOf(name);
        f.count += 1;
        f.x += x;
        f.y += y;
        f.box = [Math.min(f.box[0], x), Math.min(f.box[1], y), Math.max(f.box[2], x), Math.max(f.box[3], y)];
        break;
      }
    }
  }
  for (const f of names.map((name) => found[name])) {
    if (f.count) {
      f.x /= f.count;
      f.y /= f.count;
    }
  }
  return found;
}


// Where two screenshots (same size, {image, found}) differ: the proxy's move
// (pixels), the changed pixels, the share of them in the box around the
// proxy and its force arrow at either time (grown by twice the proxy's
// size), and the share of the proxy's pixels at either time that changed.
export function differenceNearTool(a, b) {
  const pa = a.found.proxy;
  const pb = b.found.proxy;
  const boxes = [pa.box, pb.box, a.found.force.box, b.found.force.box].filter((q) => q[0] <= q[2]);
  const grow = 2 * Math.max(pa.box[2] - pa.box[0], pb.box[2] - pb.box[0], 10);
  const box = [Math.min(...boxes.map((q) => q[0])) - grow, Math.min(...boxes.map((q) => q[1])) - grow,
               Math.max(...boxes.map((q) => q[2])) + grow, Math.max(...boxes.map((q) => q[3])) + grow];
  let changed = 0;
  let inside = 0;
  let proxyPixels = 0;
  let proxyChanged = 0;
  const proxyLabel = 1 + Object.keys(kChroma).indexOf('proxy');
  const { width, height } = a.image;
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const o = 4 * (y * width + x);
      const d = Math.abs(a.image.pixels[o] - b.image.pixels[o]) + Math.abs(a.image.pixels[o + 1] - b.image.pixels[o + 1]) +
                Math.abs(a.image.pixels[o + 2] - b.image.pixels[o + 2]);
      const isProxy = a.found.labels[y * width + x] === proxyLabel || b.found.labels[y * width + x] === proxyLabel;
      proxyPixels += isProxy;
      if (d < 40) continue;
      proxyChanged += isProxy;
      ++changed;
      if (x >= box[0] && x <= box[2] && y >= box[1] && y <= box[3]) ++inside;
    }
  }
  return { moved: Math.hypot(pa.x - pb.x, pa.y - pb.y), changed, near: changed ? inside / changed : 0,
           proxyChanged: proxyPixels ? proxyChanged / proxyPixels : 0 };
}
