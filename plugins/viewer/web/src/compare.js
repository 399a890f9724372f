// Runs side by side (trephine view RUN_A RUN_B ..., or a study's folder): a
// 3D view per run in a grid, on one clock and one time slider, their
// cameras linked (turning one turns all), the brain coloured on one range
// for all, and the plots of every run overlaid, with a row for each run's
// |F| less the first run's at the same time. window.trephineViewer reports
// as the viewer of one run does, with `runs` (per run: its frame and
// triangles) and `cameras()`.
import { RunData } from './runData.js';
import { Scene3d } from './scene3d.js';
import { Plots, eventColours, curvesCanvas } from './plots.js';
import { Legend } from './legend.js';
import { ViewControls, kStandardViews } from './viewControls.js';
import { addSelect, addEventMarks, runEvents, startTimeOf, speedOf } from './pageParts.js';
import { kMeshModes, meshModesOf } from './colouring.js';
import { niceTicks, tickLabel } from './colourMap.js';

// A colour per run, for its curves and its view's label.
export const kRunColours = ['#f2553a', '#4f8ff5', '#5cd65c', '#e0b83f', '#c77dff', '#3fd6d0'];

class ComparisonPlots extends Plots {
  constructor(canvas, runs, end, onSeek, events) {
    super(canvas, runs[0].plots, end, onSeek, events);
    this.runs = runs;
  }

  series() {
    return this.runs.some((r) => r.plots) ? [{ key: 'force' }, { key: 'penetration' }] : [];
  }

  // Per run, |F| (N) and penetration (mm) at time t; and |F| less the first run's.
  valuesAt(t) {
    const values = {};
    const first = this.runs[0].plots;
    this.runs.forEach((run, k) => {
      if (!run.plots) return;
      const i = this.sampleAt(t, run.plots);
      values[`force_${k}`] = i >= 0 ? run.plots.force[i] : NaN;
      values[`penetration_${k}`] = i >= 0 ? run.plots.penetration[i] : NaN;
      if (k > 0 && first) {
        const j = this.sampleAt(t, first);
        values[`difference_${k}`] = values[`force_${k}`] - (j >= 0 ? first.force[j] : NaN);
      }
    });
    return values;
  }

  readoutLine(t, values) {
    return `t ${t.toFixed(3)} s  |F| (N) ` + this.runs.map((run, k) => `${k}: ${Number(values[`force_${k}`]).toPrecision(3)}`).join('  ') +
      (values.difference_1 !== undefined ? `  1 less 0: ${Number(values.difference_1).toPrecision(3)}` : '');
  }

  drawCurves(width, height, scale) {
    const { canvas, g } = curvesCanvas(width, height, scale);
    const m = this.margin;
    const plotWidth = width - m.left - m.right;
    const x = (t) => m.left + ((t - this.start) / (this.end - this.start)) * plotWidth;
    // |F| - |F| of run 0, on run k's samples.
    const differences = this.runs.map((run, k) => {
      if (k === 0 || !run.plots || !this.runs[0].plots) return null;
      const first = this.runs[0].plots;
      return run.plots.t.map((t, i) => {
        const j = this.sampleAt(t, first);
        return run.plots.force[i] - (j >= 0 ? first.force[j] : 0);
      });
    });
    const rows = [
      { label: '|F| on the hand', unit: 'N', values: this.runs.map((r) => r.plots && r.plots.force), signed: false },
      { label: 'penetration', unit: 'mm', values: this.runs.map((r) => r.plots && r.plots.penetration), signed: false },
      { label: `|F| less run 0's`, unit: 'N', values: differences, signed: true },
    ];
    const rowHeight = (height - m.top - m.bottom) / rows.length;
    rows.forEach((row, r) => {
      let high = 0;
      for (const values of row.values) if (values) for (const v of values) if (Number.isFinite(v)) high = Math.max(high, Math.abs(v));
      const low = row.signed ? -Math.max(high, 1e-9) : 0;
      high = Math.max(high, 1e-9);
      const ticks = niceTicks(low, high, row.signed ? 5 : 3);
      const top = m.top + r * rowHeight + 4;
      const plotHeight = rowHeight - 8;
      const y = (v) => top + plotHeight * (1 - (v - low) / (high - low));
      g.strokeStyle = '#555';
      g.strokeRect(m.left, top, plotWidth, plotHeight);
      g.textAlign = 'right';
      g.fillStyle = '#ccc';
      for (const tick of ticks) g.fillText(tickLabel(tick, ticks), m.left - 4, y(tick) + 4);
      g.textAlign = 'left';
      g.fillText(`${row.label} (${row.unit})`, m.left + 4, top + 11);
      row.values.forEach((values, k) => {
        if (!values) return;
        const times = this.runs[k].plots.t;
        g.strokeStyle = kRunColours[k % kRunColours.length];
        g.lineWidth = 1.2;
        // Later runs dashed: where runs agree, the first shows between the dashes.
        g.setLineDash(k === 0 ? [] : [6, 4]);
        g.beginPath();
        for (let i = 0; i < values.length; ++i) {
          if (i === 0) g.moveTo(x(times[i]), y(values[i]));
          else g.lineTo(x(times[i]), y(values[i]));
        }
        g.stroke();
        g.setLineDash([]);
      });
    });
    this.drawTimeAxisAndEvents(g, width, height, plotWidth, x);
    return canvas;
  }
}

export function startComparison(manifests, status, report, warn) {
  const parameters = new URLSearchParams(window.location.search);
  document.getElementById('title').textContent = `${manifests.length} runs side by side`;
  const end = Math.max(...manifests.map((m) => m.end));
  const grid = document.getElementById('view');
  grid.classList.add('comparison');
  grid.style.display = 'grid';
  const columns = manifests.length <= 3 ? manifests.length : Math.ceil(manifests.length / 2);
  grid.style.gridTemplateColumns = `repeat(${columns}, 1fr)`;
  grid.style.gridTemplateRows = `repeat(${Math.ceil(manifests.length / columns)}, 1fr)`;
  const runs = manifests.map((manifest, k) => {
    const cell = document.createElement('div');
    cell.className = 'run-view';
    cell.dataset.run = String(k);
    cell.style.position = 'relative';
    cell.style.minHeight = '0';
    const label = document.createElement('div');
    label.className = 'run-label';
    label.textContent = `${k}: ${manifest.source || manifest.name}`;
    label.style.color = kRunColours[k % kRunColours.length];
    grid.append(cell);
    const scene = new Scene3d(cell);
    cell.append(label);
    // Each view follows its pane's size (the grid settles after the views are made).
    new ResizeObserver(() => {
      scene.setPixelScale(scene.pixelScale);
      scene.render();
    }).observe(cell);
    scene.end = end;
    return { manifest, data: new RunData(manifest, k), scene, cell, shown: -1, events: runEvents(manifest) };
  });
  // One range per colour quantity over all runs: a colour is a value in every view.
  const ranges = {};
  for (const run of runs)
    for (const part of run.manifest.parts)
      for (const [quantity, value] of Object.entries(part.ranges || {})) ranges[quantity] = Math.max(ranges[quantity] || 0, value);
  const legend = new Legend(runs[runs.length - 1].cell);
  const controls = new ViewControls(runs[0].scene, runs[0].cell);
  status.controls = controls.state;
  Object.defineProperty(status, 'legends', { get: () => legend.state(), enumerable: true });
  status.runs = runs.map(() => ({ frame: -1, triangles: {} }));

  // Linked cameras: a change to one is copied to the others.
  let copying = false;
  for (const run of runs) {
    run.scene.renderer.getActiveCamera().onModified(() => {
      if (copying) return;
      copying = true;
      const from = run.scene.renderer.getActiveCamera();
      for (const other of runs) {
        if (other === run) continue;
        const camera = other.scene.renderer.getActiveCamera();
        camera.setPosition(...from.getPosition());
        camera.setFocalPoint(...from.getFocalPoint());
        camera.setViewUp(...from.getViewUp());
        camera.setViewAngle(from.getViewAngle());
        other.scene.renderer.resetCameraClippingRange();
        other.scene.render();
      }
      copying = false;
    });
  }
  status.cameras = () => runs.map((run) => {
    const camera = run.scene.renderer.getActiveCamera();
    return { position: camera.getPosition(), focalPoint: camera.getFocalPoint(), viewUp: camera.getViewUp() };
  });

  const events = [];
  runs.forEach((run, k) => run.events.forEach((e) => events.push({ ...e, run: k })));
  events.sort((a, b) => a.t - b.t);
  status.events = events;
  const plots = new ComparisonPlots(document.getElementById('plots'), runs.map((r) => r.manifest), end, (t) => showTime(t), events);
  status.plots = plots;
  let maxForce = 0;
  for (const run of runs) if (run.manifest.plots) for (const f of run.manifest.plots.force) maxForce = Math.max(maxForce, f);

  const slider = document.getElementById('time');
  const clock = document.getElementById('clock');
  slider.max = String(end);
  slider.step = String(Math.max(end / 2000, 1e-4));
  let time = 0;
  let playing = false;
  const drawRun = (run, k, index) => {
    const manifest = run.manifest;
    let upgrade = false;
    manifest.frames[index].states.forEach((state, p) => {
      if (state < 0) return;
      const part = manifest.parts[p];
      const value = part.states[state];
      if (typeof value === 'string') {
        run.scene.show(part.name, part.kind, state, [run.data.file(value)]);
        return;
      }
      // A skull's still level when the clock stands and it is at hand (else
      // the moving level, and the still one is loaded and drawn after).
      const still = !playing && value.stillBlocks.length > 0 && run.data.isAtHand(value.stillBlocks);
      upgrade = upgrade || (!playing && !still && value.stillBlocks.length > 0);
      const names = still ? value.stillBlocks : value.blocks;
      run.scene.show(part.name, part.kind, state, names.map((name) => run.data.file(name)), still ? 'still' : 'moving');
    });
    if (upgrade) {
      run.data.require(run.data.namesOf(index, true)).then(() => {
        if (run.shown === index && !playing) drawRun(run, k, index);
      }, report);
    }
    if (!run.scene.cameraSet) {
      const bounds = run.scene.renderer.computeVisiblePropBounds();
      run.scene.setForceScale(maxForce, Math.hypot(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]));
      for (const part of run.scene.parts.values()) if (part.proxySource) part.key = undefined;
      if (k === 0) {
        run.scene.resetCameraOnce();
        controls.rememberHome();
        const view = parameters.get('view');
        if (view && kStandardViews[view]) controls.standardView(view);
        else if (view) warn(`view=${view}: not one of ${Object.keys(kStandardViews).join(', ')}`);
      } else {
        run.scene.cameraSet = true;
      }
    }
    run.scene.setTime(time);
    run.scene.render();
    run.shown = index;
    status.runs[k].frame = index;
    for (const part of manifest.parts) status.runs[k].triangles[part.name] = run.scene.triangleCount(part.name);
  };
  const showTime = (t) => {
    time = Math.min(Math.max(t, 0), end);
    status.time = time;
    slider.value = String(time);
    clock.textContent = `${time.toFixed(3)} s`;
    plots.setTime(time);
    const loads = runs.map((run, k) => {
      const index = run.data.frameAt(time);
      if (index === run.shown) return Promise.resolve();
      const names = run.data.namesOf(index);
      const draw = () => {
        if (run.data.frameAt(time) === index) drawRun(run, k, index);
      };
      if (run.data.isAtHand(names)) {
        draw();
        return Promise.resolve();
      }
      return run.data.require(names).then(draw);
    });
    Promise.all(loads).then(() => {
      // The first run's camera is set first; the others follow it.
      const camera = runs[0].scene.renderer.getActiveCamera();
      camera.modified();
      status.frame = runs[0].shown;
      status.framesDrawn += 1;
      if (!status.ready && runs.every((run) => run.shown >= 0)) {
        status.ready = true;
        status.openSeconds = performance.now() / 1000;
      }
    }, report);
  };
  status.seek = showTime;
  // Renders every view again (for measuring the drawing alone).
  status.render = () => {
    for (const run of runs) run.scene.render();
  };
  slider.addEventListener('input', () => showTime(Number(slider.value)));

  // Part toggles and the brain's colour, for every view.
  const toggles = document.getElementById('parts');
  const hidden = new Set((parameters.get('hide') || '').split(',').filter(Boolean));
  for (const part of runs[0].manifest.parts) {
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = !hidden.has(part.name);
    const apply = () => {
      for (const run of runs) {
        run.scene.setHidden(part.name, !box.checked);
        run.scene.render();
      }
      legend.setVisible(part.name, box.checked);
    };
    box.addEventListener('change', apply);
    apply();
    label.append(box, ` ${part.name}`);
    toggles.append(label);
  }
  const mesh = runs[0].manifest.parts.find((p) => p.kind === 'mesh');
  if (mesh) {
    const modes = meshModesOf({ ranges });
    const wanted = parameters.get('brain');
    const initial = modes.includes(wanted) ? wanted : modes.includes('displacement') ? 'displacement' : modes[0];
    const apply = (mode) => {
      for (const run of runs) {
        run.scene.setColouring(mesh.name, mode, ranges);
        run.scene.render();
      }
      const spec = kMeshModes[mode];
      if (spec) legend.show(mesh.name, `${spec.title}, all runs`, 0, ranges[spec.range] || 1);
      else legend.hide(mesh.name);
    };
    addSelect(document.getElementById('colours'), `${mesh.name} colour`,
              modes.map((m) => [m, kMeshModes[m] ? kMeshModes[m].title : 'tissue']), initial, apply, `colour-${mesh.name}`);
    apply(initial);
  }
  // Standard views on the first view (the others follow).
  const views = document.getElementById('views');
  for (const name of ['anterior', 'posterior', 'left', 'right', 'superior', 'reset']) {
    const button = document.createElement('button');
    button.textContent = name === 'reset' ? 'Reset view' : name[0].toUpperCase() + name.slice(1);
    button.dataset.view = name;
    button.addEventListener('click', () => (name === 'reset' ? controls.reset() : controls.standardView(name)));
    views.append(button);
  }
  addEventMarks(events, end, showTime);
  const colours = eventColours(events);
  document.querySelectorAll('#marks .mark').forEach((mark, i) => {
    mark.title = `run ${events[i].run}: ${mark.title}`;
    mark.style.background = colours[events[i].kind];
  });
  // Play: one clock for all.
  const play = document.getElementById('play');
  let last = 0;
  const speed = speedOf(parameters, warn);
  for (const name of ['skull', 'ct', 'opacity'])
    if (parameters.get(name) !== null) warn(`${name}=: runs side by side have no ${name === 'ct' ? 'CT volume' : name === 'skull' ? 'skull colours' : 'opacity'} (open a run alone for it)`);
  const tick = (now) => {
    if (!playing) return;
    const step = ((now - last) / 1000) * speed;
    last = now;
    if (time >= end) {
      playing = false;
      play.textContent = 'Play';
      return;
    }
    showTime(time + step);
    requestAnimationFrame(tick);
  };
  play.addEventListener('click', () => {
    playing = !playing;
    play.textContent = playing ? 'Pause' : 'Play';
    if (playing) {
      if (time >= end) showTime(0);
      last = performance.now();
      requestAnimationFrame(tick);
    }
  });
  showTime(startTimeOf(parameters, warn));
}
