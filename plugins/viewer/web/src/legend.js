// The colour legend over the 3D view: what is coloured (with its unit), the
// colour bar and its ticks. One per coloured part, stacked at the right.
import { kTurboBytes, niceTicks, tickLabel } from './colourMap.js';

export class Legend {
  constructor(container) {
    this.box = document.createElement('div');
    this.box.className = 'legend';
    container.append(this.box);
    this.shown = new Map();  // part -> {title, unit, min, max, element}
    this.hiddenParts = new Set();  // parts the user hid: their legends too
  }

  setVisible(part, visible) {
    if (visible) this.hiddenParts.delete(part);
    else this.hiddenParts.add(part);
    const entry = this.shown.get(part);
    if (entry) entry.element.style.display = visible ? '' : 'none';
  }

  // Shows part's legend: `title` (what, with its unit), on [min, max].
  show(part, title, min, max) {
    let entry = this.shown.get(part);
    if (entry && entry.title === title && entry.min === min && entry.max === max) return;
    if (!entry) {
      entry = { element: document.createElement('div') };
      entry.element.className = 'legend-entry';
      entry.element.dataset.part = part;
      entry.element.style.display = this.hiddenParts.has(part) ? 'none' : '';
      this.box.append(entry.element);
      this.shown.set(part, entry);
    }
    Object.assign(entry, { title, min, max });
    const element = entry.element;
    element.replaceChildren();
    const heading = document.createElement('div');
    heading.className = 'legend-title';
    heading.textContent = `${part}: ${title}`;
    const body = document.createElement('div');
    body.className = 'legend-body';
    const bar = document.createElement('canvas');
    bar.className = 'legend-bar';
    bar.width = 14;
    bar.height = 120;
    const g = bar.getContext('2d');
    for (let y = 0; y < bar.height; ++y) {
      const k = 3 * Math.round((255 * (bar.height - 1 - y)) / (bar.height - 1));
      g.fillStyle = `rgb(${kTurboBytes[k]},${kTurboBytes[k + 1]},${kTurboBytes[k + 2]})`;
      g.fillRect(0, y, bar.width, 1);
    }
    const labels = document.createElement('div');
    labels.className = 'legend-ticks';
    const ticks = niceTicks(min, max, 5);
    for (const tick of ticks) {
      const label = document.createElement('span');
      label.textContent = tickLabel(tick, ticks);
      label.style.top = `${(100 * (max - tick)) / (max - min || 1)}%`;
      labels.append(label);
    }
    body.append(bar, labels);
    element.append(heading, body);
  }

  hide(part) {
    const entry = this.shown.get(part);
    if (!entry) return;
    entry.element.remove();
    this.shown.delete(part);
  }

  // For the page's status: what each legend says.
  state() {
    return Object.fromEntries([...this.shown].map(([part, e]) => [part, { title: e.title, min: e.min, max: e.max,
                                                                           shown: !this.hiddenParts.has(part) }]));
  }
}
