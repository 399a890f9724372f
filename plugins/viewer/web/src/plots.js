// The force on the hand (N) and the penetration (mm) over time, under the 3D
// view; a line marks the time shown, and a click on a plot goes to its time.
const kSeries = [
  { key: 'force', label: '|F| (N)', colour: '#f2553a' },
  { key: 'penetration', label: 'penetration (mm)', colour: '#4f8ff5' },
];

export class Plots {
  constructor(canvas, plots, end, onSeek) {
    this.canvas = canvas;
    this.plots = plots;
    this.end = Math.max(end, 1e-6);
    this.time = 0;
    this.margin = { left: 64, right: 12, top: 8, bottom: 22 };
    canvas.addEventListener('click', (event) => {
      const box = canvas.getBoundingClientRect();
      const x = event.clientX - box.left;
      const width = box.width - this.margin.left - this.margin.right;
      if (width <= 0) return;
      onSeek(Math.min(Math.max((x - this.margin.left) / width, 0), 1) * this.end);
    });
    window.addEventListener('resize', () => this.draw());
  }

  setTime(t) {
    this.time = t;
    this.draw();
  }

  // The curves are drawn once per size into an offscreen canvas; a new time
  // only copies them and draws its line (software-rendered browsers redraw
  // long paths slowly).
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
    const plotWidth = width - this.margin.left - this.margin.right;
    const x = this.margin.left + (this.time / this.end) * plotWidth;
    g.strokeStyle = '#fff';
    g.beginPath();
    g.moveTo(x, 0);
    g.lineTo(x, height);
    g.stroke();
  }

  drawCurves(width, height, scale) {
    const canvas = document.createElement('canvas');
    canvas.width = Math.max(1, Math.round(width * scale));
    canvas.height = Math.max(1, Math.round(height * scale));
    const g = canvas.getContext('2d');
    g.setTransform(scale, 0, 0, scale, 0, 0);
    g.font = '11px sans-serif';
    const m = this.margin;
    const plotWidth = width - m.left - m.right;
    const series = this.plots ? kSeries.filter((s) => this.plots[s.key]) : [];
    if (!series.length || plotWidth <= 0) {
      g.fillStyle = '#999';
      g.fillText('no trace.csv in this run: no plots', m.left, 20);
      return canvas;
    }
    const rowHeight = height / series.length;
    const times = this.plots.t;
    const x = (t) => m.left + (t / this.end) * plotWidth;
    series.forEach((s, row) => {
      const values = this.plots[s.key];
      let high = 0;
      for (const v of values) if (v > high) high = v;
      if (high <= 0) high = 1;
      const top = row * rowHeight + m.top;
      const plotHeight = rowHeight - m.top - m.bottom;
      const y = (v) => top + plotHeight * (1 - v / high);
      g.strokeStyle = '#555';
      g.strokeRect(m.left, top, plotWidth, plotHeight);
      g.fillStyle = '#ccc';
      g.fillText(s.label, 4, top + 10);
      g.fillText(high.toPrecision(3), 4, top + 24);
      g.fillText('0', 4, top + plotHeight);
      g.strokeStyle = s.colour;
      g.beginPath();
      for (let i = 0; i < values.length; ++i) {
        if (i === 0) g.moveTo(x(times[i]), y(values[i]));
        else g.lineTo(x(times[i]), y(values[i]));
      }
      g.stroke();
      g.fillStyle = '#999';
      g.fillText(`${this.end.toFixed(2)} s`, m.left + plotWidth - 40, top + plotHeight + 14);
    });
    return canvas;
  }
}
