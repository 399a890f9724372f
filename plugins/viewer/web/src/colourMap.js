// The colour map of every quantity the viewer colours by: Turbo (Mikhailov,
// Google 2019), a rainbow whose lightness rises and falls smoothly, so that
// its hue alone tells the value (blue low, green middle, red high) under any
// shading; with its polynomial fit. And the "nice" ticks of a range.

// RGB (0..1) of the value t in [0, 1].
export function turbo(t) {
  const x = Math.min(Math.max(t, 0), 1);
  const poly = (c) => c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
  const clamp = (v) => Math.min(Math.max(v, 0), 1);
  return [
    clamp(poly([0.13572138, 4.6153926, -42.66032258, 132.13108234, -152.94239396, 59.28637943])),
    clamp(poly([0.09140261, 2.19418839, 4.84296658, -14.18503333, 4.27729857, 2.82956604])),
    clamp(poly([0.1066733, 12.64194608, -60.58204836, 110.36276771, -89.90310912, 27.34824973])),
  ];
}

// Where the viewer's map starts on Turbo: Turbo's own low end is near black
// (luminance 0.10), which on the dark background drew a brain at rest (its
// lowest value everywhere) as a dark hole; from 0.1 the lowest value is a
// clear blue (luminance 0.37), and the rest of the map is Turbo's.
export const kMapStart = 0.1;

// A table of 256 entries (bytes RGB) for colouring many values fast: the
// value t in [0, 1] at Turbo's kMapStart + (1 - kMapStart) t.
export const kTurboBytes = (() => {
  const table = new Uint8Array(256 * 3);
  for (let i = 0; i < 256; ++i) {
    const [r, g, b] = turbo(kMapStart + (1 - kMapStart) * (i / 255));
    table.set([Math.round(255 * r), Math.round(255 * g), Math.round(255 * b)], 3 * i);
  }
  return table;
})();

// Writes the colour of `value` on [low, high] at `out[3 * i]` (bytes).
export function colourInto(out, i, value, low, high) {
  const t = high > low ? (value - low) / (high - low) : 0;
  const k = 3 * Math.round(255 * Math.min(Math.max(Number.isFinite(t) ? t : 0, 0), 1));
  out[3 * i] = kTurboBytes[k];
  out[3 * i + 1] = kTurboBytes[k + 1];
  out[3 * i + 2] = kTurboBytes[k + 2];
}

// About `count` round ticks (1, 2 or 5 times a power of ten) over [low, high].
export function niceTicks(low, high, count = 5) {
  if (!(high > low)) return [low];
  const raw = (high - low) / Math.max(count - 1, 1);
  const power = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= raw) || 10 * power;
  const ticks = [];
  for (let v = Math.ceil(low / step - 1e-9) * step; v <= high + 1e-9 * step; v += step) ticks.push(Math.abs(v) < 1e-12 * step ? 0 : v);
  return ticks;
}

// A tick's label: as few digits as the step needs.
export function tickLabel(value, ticks) {
  const step = ticks.length > 1 ? Math.abs(ticks[1] - ticks[0]) : Math.abs(value) || 1;
  const decimals = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  return value.toFixed(Math.min(decimals, 6));
}
