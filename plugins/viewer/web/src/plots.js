// The force on the hand (N) and the penetration (mm) over time, under the 3D
// view: each with its axis ticked in its unit and the time axis in s; the
// run's events (breakthrough, tool change, contact warning, pedal, watchdog,
// ...) as vertical marks, one colour a kind; a line at the time shown; a
// read-out of the values under the cursor; a click goes to its time. With
// several tools, trace.csv's tool is drawn solid and every other tool's
// (trace.PATH.csv) dashed in its own pattern, each named in a key at the top.
import { niceTicks, tickLabel } from './colourMap.js';

const kSeries = [
  { key: 'force', label: '|F| on the hand', unit: 'N', colour: '#f2553a' },
  { key: 'penetration', label: 'penetration', unit: 'mm', colour: '#4f8ff5' },
];
// Dash patterns of the other tools' curves, in the order of their paths.
export const kToolDashes = [[6, 3], [2, 2], [8, 3, 2, 3], [1, 4]];
// Colours of event kinds, in the order kinds are first met (sorted by name).
export const kEventColours = ['#ffd23f', '#3fe0d0', '#ff7ad9', '#9dff5c', '#ffa24f', '#b58cff', '#ffffff'];

// An offscreen canvas of `width` x `height` CSS pixels at `scale` device
// pixels each, drawn on in CSS pixels with the plots' font.
export function curvesCanvas(width, height, scale) {
  const canvas = document.createElement('canvas');
  canvas.width = Math.max(1, Math.round(width * scale));
  canvas.height = Math.max(1, Math.round(height * scale));
  const g = canvas.getContext('2d');
  g.setTransform(scale, 0, 0, scale, 0, 0);
  g.font = '11px sans-serif';
  return { canvas, g };
}

export function eventColours(events) {
  const kinds = [...new Set(events.map((e) => e.kind))].sort();
  return Object.fromEntries(kinds.map((kind, i) => [kind, kEventColours[i % kEventColours.length]]));
}

export class Plots {
  constructor(canvas, plots, end, onSeek, events = []) {
    this.canvas = canvas;
    this.plots = plots;
    this.end = Math.max(end, 1e-6);
    this.start = 0;
    this.time = 0;
    this.events = events;
    this.colours = eventColours(events);
    this.tools = [];     // every other tool's plots: {name, t, force, penetration}
    this.cursor = null;  // CSS x of the mouse over the plots
    this.readout = null;
    this.margin = { left: 58, right: 12, top: 18, bottom: 18 };
    canvas.addEventListener('click', (event) => {
      const t = this.timeAtClient(event.clientX);
      if (t !== null) onSeek(t);
    });
    canvas.addEventListener('mousemove', (event) => {
      this.cursor = event.clientX - canvas.getBoundingClientRect().left;
      this.draw();
    });
    canvas.addEventListener('mouseleave', () => {
      this.cursor = null;
      this.draw();
    });
    new ResizeObserver(() => this.draw()).observe(canvas);
  }

  // The time under a client x, or null outside the plots.
  timeAtClient(clientX) {
    const box = this.canvas.getBoundingClientRect();
    const width = box.width - this.margin.left - this.margin.right;
    if (width <= 0) return null;
    const f = Math.min(Math.max((clientX - box.left - this.margin.left) / width, 0), 1);
    return this.start + f * (this.end - this.start);
  }

  // The client x of time t (for tests and the slider's marks).
  clientXOf(t) {
    const box = this.canvas.getBoundingClientRect();
    const width = box.width - this.margin.left - this.margin.right;
    return box.left + this.margin.left + ((t - this.start) / (this.end - this.start)) * width;
  }

  // The other tools' plots (the manifest's toolPlots), drawn dashed beside trace.csv's.
  setTools(tools) {
    this.tools = tools.filter((tool) => tool && tool.t && tool.t.length);
    this.curves = null;
    this.draw();
  }

  setTime(t) {
    this.time = t;
    this.draw();
  }

  // Index of the last sample at or before t.
  sampleAt(t, plots = this.plots) {
    const times = plots ? plots.t : [];
    let low = 0;
    let high = times.length - 1;
    if (high < 0) return -1;
    while (low < high) {
      const middle = (low + high + 1) >> 1;
      if (times[middle] <= t) low = middle;
      else high = middle - 1;
    }
    return low;
  }

  // The curves, axes and event marks are drawn once per size into an
  // offscreen canvas; a new time or cursor only copies them and draws its
  // lines (software-rendered browsers redraw long paths slowly).
  draw() {
    const canvas = this.canvas;
    const scale = window.devicePixelRatio || 1;
    const width = canvas.clientWidth;
    const height = canvas.clientHeight;
    if (canvas.width !== Math.round(width * scale) || canvas.height !== Math.round(height * scale)) {
      canvas.width = Math.round(width * scale);
      canvas.height = Math.round(height * scale);
      this.curves = null;
    }
    if (!this.curves) this.curves = this.drawCurves(width, height, scale);
    const g = canvas.getContext('2d');
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.clearRect(0, 0, canvas.width, canvas.height);
    g.drawImage(this.curves, 0, 0);
    g.setTransform(scale, 0, 0, scale, 0, 0);
    const m = this.margin;
    const plotWidth = width - m.left - m.right;
    const x = (t) => m.left + ((t - this.start) / (this.end - this.start)) * plotWidth;
    g.strokeStyle = '#fff';
    g.lineWidth = 1;
    g.beginPath();
    g.moveTo(x(this.time), m.top);
    g.lineTo(x(this.time), height - m.bottom);
    g.stroke();
    this.readout = null;
    if (this.cursor !== null && this.cursor >= m.left && this.cursor <= width - m.right && this.plots) {
      const t = this.start + ((this.cursor - m.left) / plotWidth) * (this.end - this.start);
      const values = this.valuesAt(t);
      this.readout = { t, ...values };
      g.strokeStyle = 'rgba(255,255,255,0.45)';
      g.setLineDash([3, 3]);
      g.beginPath();
      g.moveTo(this.cursor, m.top);
      g.lineTo(this.cursor, height - m.bottom);
      g.stroke();
      g.setLineDash([]);
      const text = this.readoutLine(t, values);
      g.font = '11px sans-serif';
      const textWidth = g.measureText(text).width;
      const left = Math.min(Math.max(this.cursor + 8, m.left), width - m.right - textWidth - 6);
      g.fillStyle = 'rgba(20,22,28,0.85)';
      g.fillRect(left - 3, 1, textWidth + 6, 15);
      g.fillStyle = '#fff';
      g.fillText(text, left, 12);
    }
  }

  // The plotted values at time t (the last sample at or before it).
  valuesAt(t) {
    const i = this.sampleAt(t);
    const values = Object.fromEntries(this.series().map((s) => [s.key, i >= 0 ? this.plots[s.key][i] : NaN]));
    (this.tools || []).forEach((tool, k) => {
      const j = this.sampleAt(t, tool);
      for (const s of this.series()) values[`${s.key}_tool${k}`] = j >= 0 ? tool[s.key][j] : NaN;
    });
    return values;
  }

  readoutLine(t, values) {
    const line = `t ${t.toFixed(3)} s   ` + this.series().map((s) => `${s.label} ${values[s.key].toPrecision(3)} ${s.unit}`).join('   ');
    const tools = (this.tools || []).map((tool, k) =>
      `${tool.name}: ` + this.series().map((s) => `${values[`${s.key}_tool${k}`].toPrecision(3)} ${s.unit}`).join(' '));
    return [line, ...tools].join('   ');
  }

  series() {
    return this.plots ? kSeries.filter((s) => this.plots[s.key]) : [];
  }

  drawCurves(width, height, scale) {
    const { canvas, g } = curvesCanvas(width, height, scale);
    const m = this.margin;
    const plotWidth = width - m.left - m.right;
    const series = this.series();
    if (!series.length || plotWidth <= 0) {
      g.fillStyle = '#999';
      g.fillText('no trace.csv in this run: no plots', m.left, 20);
      return canvas;
    }
    const x = (t) => m.left + ((t - this.start) / (this.end - this.start)) * plotWidth;
    const rowHeight = (height - m.top - m.bottom) / series.length;
    const times = this.plots.t;
    series.forEach((s, row) => {
      const values = this.plots[s.key];
      let high = 0;
      for (let i = 0; i < values.length; ++i) if (times[i] >= this.start && values[i] > high) high = values[i];
      for (const tool of this.tools || [])
        for (let i = 0; i < tool[s.key].length; ++i) if (tool.t[i] >= this.start && tool[s.key][i] > high) high = tool[s.key][i];
      const ticks = niceTicks(0, high > 0 ? high : 1, 3);
      high = Math.max(high, ticks[ticks.length - 1], 1e-9);
      const top = m.top + row * rowHeight + 4;
      const plotHeight = rowHeight - 8;
      const y = (v) => top + plotHeight * (1 - v / high);
      g.strokeStyle = '#555';
      g.strokeRect(m.left, top, plotWidth, plotHeight);
      g.fillStyle = '#ccc';
      g.textAlign = 'right';
      for (const tick of ticks) {
        g.fillText(tickLabel(tick, ticks), m.left - 4, y(tick) + 4);
        g.strokeStyle = '#333';
        g.beginPath();
        g.moveTo(m.left, y(tick));
        g.lineTo(m.left + plotWidth, y(tick));
        g.stroke();
      }
      g.textAlign = 'left';
      g.fillStyle = s.colour;
      g.fillText(`${s.label} (${s.unit})`, m.left + 4, top + 11);
      g.strokeStyle = s.colour;
      g.lineWidth = 1.2;
      g.beginPath();
      let started = false;
      for (let i = 0; i < values.length; ++i) {
        if (times[i] < this.start) continue;
        if (!started) g.moveTo(x(times[i]), y(values[i]));
        else g.lineTo(x(times[i]), y(values[i]));
        started = true;
      }
      g.stroke();
      // Every other tool, dashed in its own pattern.
      (this.tools || []).forEach((tool, k) => {
        g.setLineDash(kToolDashes[k % kToolDashes.length]);
        g.beginPath();
        let begun = false;
        for (let i = 0; i < tool[s.key].length; ++i) {
          if (tool.t[i] < this.start) continue;
          if (!begun) g.moveTo(x(tool.t[i]), y(tool[s.key][i]));
          else g.lineTo(x(tool.t[i]), y(tool[s.key][i]));
          begun = true;
        }
        g.stroke();
        g.setLineDash([]);
      });
      g.lineWidth = 1;
    });
    if ((this.tools || []).length) this.drawToolKey(g, m.left + 4, m.top + 26);
    this.drawTimeAxisAndEvents(g, width, height, plotWidth, x);
    return canvas;
  }

  // Which curve is which tool: trace.csv's solid, the others dashed.
  drawToolKey(g, left, top) {
    const entries = [{ name: "trace.csv's tool", dash: [] }, ...this.tools.map((tool, k) => ({ name: tool.name, dash: kToolDashes[k % kToolDashes.length] }))];
    let x = left;
    g.strokeStyle = '#ddd';
    g.fillStyle = '#ddd';
    for (const entry of entries) {
      g.setLineDash(entry.dash);
      g.beginPath();
      g.moveTo(x, top - 4);
      g.lineTo(x + 22, top - 4);
      g.stroke();
      g.setLineDash([]);
      g.fillText(entry.name, x + 26, top);
      x += 26 + g.measureText(entry.name).width + 14;
    }
  }

  drawTimeAxisAndEvents(g, width, height, plotWidth, x) {
    const m = this.margin;
    // The time axis.
    const ticks = niceTicks(this.start, this.end, Math.max(2, Math.floor(plotWidth / 90)));
    g.fillStyle = '#aaa';
    g.textAlign = 'center';
    for (const tick of ticks) g.fillText(tickLabel(tick, ticks), x(tick), height - 5);
    g.textAlign = 'right';
    g.fillText('t (s)', m.left - 12, height - 5);
    g.textAlign = 'left';
    // The events, over both rows, and their kinds at the top right.
    // Two pixels wide on whole pixels: the kind's colour, unblended.
    g.lineWidth = 2;
    for (const e of this.events) {
      if (e.t < this.start || e.t > this.end) continue;
      g.strokeStyle = this.colours[e.kind];
      g.beginPath();
      g.moveTo(Math.round(x(e.t)), m.top);
      g.lineTo(Math.round(x(e.t)), height - m.bottom);
      g.stroke();
    }
    g.lineWidth = 1;
    let right = width - m.right;
    for (const kind of Object.keys(this.colours).reverse()) {
      const count = this.events.filter((e) => e.kind === kind).length;
      const label = `${kind.replace(/_/g, ' ')} (${count})`;
      const w = g.measureText(label).width + 16;
      right -= w;
      g.fillStyle = this.colours[kind];
      g.fillRect(right, 5, 8, 8);
      g.fillText(label, right + 11, 13);
      right -= 6;
    }
  }
}
