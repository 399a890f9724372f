// The viewer of a trephine run: the 3D view, a time slider with the run's
// events, a play button, the colour maps and their legends, the view's
// controls (viewControls.js) and the plots. URL parameters (for links and
// tests): t=SECONDS starts there, play=1 starts playing, speed=X plays X
// times real time, hide=a,b hides those parts, opacity=X draws the skull at
// that opacity (0..1), brain=MODE and skull=MODE colour them (colouring.js),
// view=NAME opens a standard view, scale=X draws at X of the display's
// pixels, playScale=X while playing (0.35).
// window.trephineViewer reports its state: ready (the first frame drawn),
// openSeconds, time, frame, framesDrawn, triangles per part, levels (of
// the block parts: 'moving' or 'still'), colouring and legends, the triad
// and scale bar, events, the plots' read-out, renderer, errors; and
// seek(t).
import { RunData } from './runData.js';
import { Scene3d } from './scene3d.js';
import { Plots } from './plots.js';
import { addSelect, addEventMarks, runEvents, startTimeOf, speedOf } from './pageParts.js';
import { startComparison } from './compare.js';
import { startLive } from './live.js';
import { Legend } from './legend.js';
import { ViewControls, kStandardViews } from './viewControls.js';
import { SkullVolume } from './skullVolume.js';
import { CtVolume } from './ctVolume.js';
import { kMeshModes, kSkullModes, meshModesOf, densityRange } from './colouring.js';

const status = {
  ready: false,
  openSeconds: NaN,
  time: 0,
  frame: -1,
  framesDrawn: 0,
  triangles: {},
  errors: [],
  renderer: '',
};
window.trephineViewer = status;

function report(error) {
  const message = error && error.message ? error.message : String(error);
  status.errors.push(message);
  console.error(message);
  const box = document.getElementById('message');
  if (box) box.textContent = message;
}

// A URL parameter the page cannot follow: said on the page, and kept in
// status.warnings; the page goes on with its default.
function warn(text) {
  status.warnings = status.warnings || [];
  status.warnings.push(text);
  const box = document.getElementById('message');
  if (box) box.textContent = box.textContent ? `${box.textContent}; ${text}` : text;
}

function rendererName() {
  const gl = document.createElement('canvas').getContext('webgl2');
  if (!gl) return 'no WebGL2';
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}

// A checkbox per part, and the skull's opacity (to see the brain inside).
function addPartToggles(manifest, scene, parameters, legend = null) {
  const toggles = document.getElementById('parts');
  const hidden = new Set((parameters.get('hide') || '').split(',').filter(Boolean));
  for (const name of hidden)
    if (!manifest.parts.some((part) => part.name === name))
      warn(`hide=${name}: no such part (the parts: ${manifest.parts.map((part) => part.name).join(', ')})`);
  for (const part of manifest.parts) {
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = !hidden.has(part.name);
    scene.setHidden(part.name, !box.checked);
    if (legend) legend.setVisible(part.name, box.checked);
    box.addEventListener('change', () => {
      scene.setHidden(part.name, !box.checked);
      if (legend) legend.setVisible(part.name, box.checked);
      scene.render();
    });
    label.append(box, ` ${part.name}`);
    toggles.append(label);
    if (part.kind === 'blocks') {
      const opacityLabel = document.createElement('label');
      opacityLabel.className = 'opacity';
      opacityLabel.textContent = `${part.name} opacity `;
      const opacity = document.createElement('input');
      opacity.type = 'range';
      opacity.min = '0.1';
      opacity.max = '1';
      opacity.step = '0.05';
      opacity.value = parameters.get('opacity') || '1';
      opacity.title = `${part.name} opacity`;
      scene.setOpacity(part.name, Number(opacity.value));
      opacity.addEventListener('input', () => {
        scene.setOpacity(part.name, Number(opacity.value));
        scene.render();
      });
      opacityLabel.append(opacity);
      toggles.append(opacityLabel);
    }
  }
}


// The skull's volume, loaded once when a view asks for it.
const skullVolumes = new Map();  // part name -> Promise of its SkullVolume
function loadSkullVolume(part, data, scene) {
  let loading = skullVolumes.get(part.name);
  if (!loading) {
    loading = data.require([part.volume.density, part.volume.removed]).then(() => {
      scene.volume = new SkullVolume(data.bytes(part.volume.density), data.bytes(part.volume.removed), part.volume.density);
      return scene.volume;
    });
    skullVolumes.set(part.name, loading);
  }
  return loading;
}

// "CT volume": the CT drawn as a volume with the drilled region (ctVolume.js).
function addCtToggle(manifest, scene, parameters, data, getTime, redraw) {
  const part = manifest.parts.find((p) => p.kind === 'blocks' && p.volume);
  if (!part) return;
  const label = document.createElement('label');
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.id = 'ct-volume';
  box.checked = parameters.get('ct') === '1';
  label.title = 'The CT as a volume rendering, the drilled region in orange (slow without a graphics card)';
  label.append(box, ' CT volume');
  document.getElementById('parts').append(label);
  const apply = () => {
    if (!box.checked && !scene.ct) return;
    loadSkullVolume(part, data, scene).then((volume) => {
      if (!scene.ct) scene.ct = new CtVolume(scene.renderer, volume);
      scene.ct.setVisible(box.checked);
      scene.ct.setTime(getTime());
      status.ct = { shown: box.checked, cutVoxels: scene.ct.cutVoxels };
      redraw();
    }, report);
  };
  box.addEventListener('change', apply);
  apply();
}

// The colour of each part: a select per colourable part, its legend, and
// the skull's volume loaded when a mode needs it.
function addColourControls(manifest, scene, legend, parameters, data, redraw) {
  const container = document.getElementById('colours');
  for (const part of manifest.parts) {
    if (part.kind === 'mesh') {
      const modes = meshModesOf(part);
      if (modes.length < 2) continue;
      const wanted = parameters.get(part.name) || parameters.get('brain');
      if (wanted && !modes.includes(wanted)) warn(`brain=${wanted}: not one of ${modes.join(', ')}`);
      const initial = modes.includes(wanted) ? wanted : modes.includes('displacement') ? 'displacement' : modes[0];
      const apply = (mode) => {
        scene.setColouring(part.name, mode, part.ranges);
        const spec = kMeshModes[mode];
        if (spec) legend.show(part.name, spec.title, 0, part.ranges[spec.range] || 1);
        else legend.hide(part.name);
        redraw();
      };
      addSelect(container, `${part.name} colour`, modes.map((m) => [m, kMeshModes[m] ? kMeshModes[m].title : 'tissue']),
                initial, apply, `colour-${part.name}`);
      apply(initial);
    } else if (part.kind === 'blocks' && part.volume) {
      const modes = Object.keys(kSkullModes);
      const wanted = parameters.get(part.name) || parameters.get('skull');
      if (wanted && !modes.includes(wanted)) warn(`skull=${wanted}: not one of ${modes.join(', ')}`);
      const initial = modes.includes(wanted) ? wanted : 'bone';
      const volume = () => loadSkullVolume(part, data, scene);
      const apply = (mode) => {
        if (!kSkullModes[mode]) {
          scene.setColouring(part.name, mode);
          legend.hide(part.name);
          redraw();
          return;
        }
        volume().then((v) => {
          scene.setColouring(part.name, mode);
          if (mode === 'density') legend.show(part.name, kSkullModes[mode].title, ...densityRange(v));
          else legend.show(part.name, kSkullModes[mode].title, 0, manifest.end);
          status.volumeLoaded = true;
          redraw();
        }, report);
      };
      addSelect(container, `${part.name} colour`, modes.map((m) => [m, kSkullModes[m] ? kSkullModes[m].title : 'bone']),
                initial, apply, `colour-${part.name}`);
      apply(initial);
    }
  }
}

// Standard views, reset, and the clipping plane.
function addViewButtons(controls, parameters) {
  const container = document.getElementById('views');
  const names = { anterior: 'Anterior', posterior: 'Posterior', left: 'Left', right: 'Right', superior: 'Superior' };
  for (const [name, text] of Object.entries(names)) {
    const button = document.createElement('button');
    button.textContent = text;
    button.dataset.view = name;
    button.title = `Look at the head from ${name === 'superior' ? 'above' : 'the ' + name}`;
    button.addEventListener('click', () => controls.standardView(name));
    container.append(button);
  }
  const reset = document.createElement('button');
  reset.textContent = 'Reset view';
  reset.dataset.view = 'reset';
  reset.title = 'Back to the view the viewer opened with';
  reset.addEventListener('click', () => controls.reset());
  container.append(reset);
  let axis = null;
  const position = document.createElement('input');
  position.type = 'range';
  position.min = '0';
  position.max = '1';
  position.step = '0.01';
  position.value = '0.5';
  position.id = 'clip-position';
  const flip = document.createElement('input');
  flip.type = 'checkbox';
  flip.id = 'clip-flip';
  const update = () => controls.setClipping(axis, Number(position.value), flip.checked);
  addSelect(container, 'clip', [['off', 'off'], ['0', 'left-right (x)'], ['1', 'front-back (y)'], ['2', 'top-bottom (z)']],
            'off', (value) => {
              axis = value === 'off' ? null : Number(value);
              update();
            }, 'clip-axis');
  const at = document.createElement('label');
  at.textContent = 'at ';
  at.append(position);
  const side = document.createElement('label');
  side.append(flip, ' other side');
  position.addEventListener('input', update);
  flip.addEventListener('change', update);
  container.append(at, side);
}



async function start() {
  // The live view's manifest sets trephineRun; trephine view's, trephineRuns.
  const runs = window.trephineRuns || (window.trephineRun ? [window.trephineRun] : []);
  const manifest = runs[0];
  if (!manifest) throw new Error('data/manifest.js is missing: write the viewer with trephine view RUN_DIR');
  window.trephineRun = manifest;
  if (runs.length > 1) {
    startComparison(runs, status, report, warn);
    return;
  }
  document.getElementById('title').textContent = manifest.name;
  status.renderer = rendererName();
  const scene = new Scene3d(document.getElementById('view'));
  const controls = new ViewControls(scene, document.getElementById('view'));
  const legend = new Legend(document.getElementById('view'));
  status.controls = controls.state;
  Object.defineProperty(status, 'legends', { get: () => legend.state(), enumerable: true });
  if (manifest.live) {
    // Served by trephine run --view: no files, a stream.
    document.getElementById('play').style.display = 'none';
    document.getElementById('time').style.display = 'none';
    const parameters = new URLSearchParams(window.location.search);
    addPartToggles(manifest, scene, parameters);
    const plots = new Plots(document.getElementById('plots'), null, 10, () => {});
    // Always moving: drawn at the playing scale of the pixels.
    scene.setPixelScale(Number(parameters.get('playScale') || 0.35));
    startLive(manifest, scene, plots, status, report);
    return;
  }
  const data = new RunData(manifest);
  const end = manifest.end;
  const slider = document.getElementById('time');
  const label = document.getElementById('clock');
  const play = document.getElementById('play');
  slider.max = String(end);
  slider.step = String(Math.max(end / 2000, 1e-4));

  const events = runEvents(manifest);
  status.events = events;
  scene.end = end;
  const plots = new Plots(document.getElementById('plots'), manifest.plots, end, (t) => seek(t), events);
  plots.setTools(manifest.toolPlots || []);
  status.plots = plots;
  let maxForce = 0;
  if (manifest.plots && manifest.plots.force) for (const f of manifest.plots.force) maxForce = Math.max(maxForce, f);

  let time = 0;
  let playing = false;
  let interacting = false;  // the user turning or moving the view
  let shown = -1;       // the frame on screen
  let wanted = -1;      // the frame being loaded
  const drawFrame = (index) => {
    drawFrameParts(index);
    if (!scene.cameraSet) {
      const bounds = scene.renderer.computeVisiblePropBounds();
      scene.setForceScale(maxForce, Math.hypot(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]));
      // The arrow was sized before the scale was known.
      for (const part of scene.parts.values()) if (part.proxySource) part.key = undefined;
      drawFrameParts(index);
      scene.resetCameraOnce();
      controls.rememberHome();
      const view = parameters.get('view');
      if (view && kStandardViews[view]) controls.standardView(view);
      else if (view) warn(`view=${view}: not one of ${Object.keys(kStandardViews).join(', ')}`);
    }
    const before = performance.now();
    scene.render();
    status.renderMs = performance.now() - before;
    shown = index;
    status.frame = index;
    status.framesDrawn += 1;
    for (const part of manifest.parts) status.triangles[part.name] = scene.triangleCount(part.name);
    if (!status.ready) {
      status.ready = true;
      // From the start of the page's loading (performance's time origin).
      status.openSeconds = performance.now() / 1000;
    }
  };
  // Draws a frame's parts; the blocks (a skull) at their still level when the
  // view stands still and that level is at hand, else at the moving level
  // while the still one loads (then drawn again).
  const drawFrameParts = (index) => {
    const still = !playing && !interacting;
    let upgrade = false;
    manifest.frames[index].states.forEach((state, p) => {
      if (state < 0) return;
      const part = manifest.parts[p];
      const value = part.states[state];
      if (typeof value === 'string') {
        scene.show(part.name, part.kind, state, [data.file(value)]);
        return;
      }
      const useStill = still && value.stillBlocks.length > 0 && data.isAtHand(value.stillBlocks);
      upgrade = upgrade || (still && !useStill && value.stillBlocks.length > 0);
      const names = useStill ? value.stillBlocks : value.blocks;
      scene.show(part.name, part.kind, state, names.map((name) => data.file(name)), useStill ? 'still' : 'moving');
    });
    if (upgrade) {
      data.require(data.namesOf(index, true)).then(() => {
        if (shown === index && !playing && !interacting) drawFrame(index);
      }, report);
    }
    status.levels = Object.fromEntries(scene.levels);
  };
  // Shows the frame of time t as soon as its files are at hand (loading them
  // if not); the latest request wins.
  const showTime = (t) => {
    time = Math.min(Math.max(t, 0), end);
    status.time = time;
    slider.value = String(time);
    label.textContent = `${time.toFixed(3)} s`;
    plots.setTime(time);
    scene.setTime(time);
    const index = data.frameAt(time);
    if (scene.ct) {
      const before = scene.ct.cutVoxels;
      scene.ct.setTime(time);
      status.ct.cutVoxels = scene.ct.cutVoxels;
      if (index === shown && before !== scene.ct.cutVoxels) scene.render();  // the cuts changed, the frame did not
    }
    if (index === shown) return;
    const names = data.namesOf(index);
    if (data.isAtHand(names)) {
      drawFrame(index);
      return;
    }
    wanted = index;
    data.require(names).then(() => {
      if (wanted === index) drawFrame(index);
    }, report);
    // Ahead of playback: the next frames' files.
    for (let k = index + 1; k < Math.min(index + 4, manifest.frames.length); ++k) data.require(data.namesOf(k)).catch(report);
  };
  const seek = (t) => showTime(t);
  status.seek = seek;
  // Where the tool's proxy is drawn: CSS pixels in the view, and its radius
  // in pixels (for tests and links), or null when there is no tool.
  status.toolOnScreen = () => {
    const tool = [...scene.parts.values()].find((part) => part.proxySource && part.hasTool);
    if (!tool) return null;
    const centre = tool.proxySource.getCenter();
    const radius = tool.proxySource.getRadius();
    const camera = scene.renderer.getActiveCamera();
    const up = camera.getViewUp();
    const onScreen = (p) => {
      const gl = scene.view.getApiSpecificRenderWindow();
      const [x, y] = gl.worldToDisplay(...p, scene.renderer);
      const [width, height] = gl.getSize();
      const box = scene.view.getContainer().getBoundingClientRect();
      return [(x / width) * box.width, (1 - y / height) * box.height];
    };
    const a = onScreen(centre);
    const b = onScreen(centre.map((v, k) => v + radius * up[k]));
    return { x: a[0], y: a[1], radius: Math.hypot(a[0] - b[0], a[1] - b[1]) };
  };
  // Zooms the camera by `factor` about the focal point (tests of the scale bar).
  status.zoomForTest = (factor) => {
    scene.renderer.getActiveCamera().zoom(factor);
    scene.render();
  };
  status.camera = () => {
    const camera = scene.renderer.getActiveCamera();
    return { position: camera.getPosition(), focalPoint: camera.getFocalPoint(), viewUp: camera.getViewUp() };
  };
  // Renders again (for measuring the drawing alone).
  status.render = () => {
    const before = performance.now();
    scene.render();
    status.renderMs = performance.now() - before;
  };

  const parameters = new URLSearchParams(window.location.search);
  let speed = 1;
  let last = 0;
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
    // Keep the coming frames' files loading while playing.
    const next = data.frameAt(time) + 1;
    if (next < manifest.frames.length && !data.isAtHand(data.namesOf(next))) data.require(data.namesOf(next)).catch(report);
    requestAnimationFrame(tick);
  };
  // While playing, the view is drawn at playScale of its pixels (a URL
  // parameter, 0.35 by default): a browser without a graphics card then keeps
  // up with the run's 30 frames a second; paused, at full resolution.
  const playScale = Number(parameters.get('playScale') || 0.35);
  const fullScale = Number(parameters.get('scale') || 1);
  const setPlaying = (on) => {
    playing = on;
    play.textContent = on ? 'Pause' : 'Play';
    scene.setPixelScale(on ? Math.min(playScale, fullScale) : fullScale);
    if (shown >= 0) drawFrame(shown);  // at the level for playing, or still
    if (on) {
      if (time >= end) showTime(0);
      last = performance.now();
      requestAnimationFrame(tick);
    }
  };
  play.addEventListener('click', () => setPlaying(!playing));
  // Turning the view: the moving level, the still one once it stops.
  const interactor = scene.view.getInteractor();
  interactor.onStartAnimation(() => {
    interacting = true;
    if (shown >= 0 && !playing) drawFrame(shown);
  });
  interactor.onEndAnimation(() => {
    interacting = false;
    if (shown >= 0 && !playing) drawFrame(shown);
  });
  slider.addEventListener('input', () => seek(Number(slider.value)));
  window.addEventListener('keydown', (event) => {
    if (event.key === ' ') setPlaying(!playing);
  });

  addPartToggles(manifest, scene, parameters, legend);
  addColourControls(manifest, scene, legend, parameters, data, () => {
    status.colouring = Object.fromEntries([...scene.colouring].map(([name, c]) => [name, c.mode]));
    if (shown >= 0) scene.render();
  });
  addCtToggle(manifest, scene, parameters, data, () => time, () => {
    if (shown >= 0) scene.render();
  });
  addViewButtons(controls, parameters);
  addEventMarks(events, end, seek);
  speed = speedOf(parameters, warn);
  if (fullScale !== 1) scene.setPixelScale(fullScale);
  showTime(startTimeOf(parameters, warn));
  if (parameters.get('play') === '1') setPlaying(true);
}

window.addEventListener('error', (event) => report(event.error || event.message));
window.addEventListener('unhandledrejection', (event) => report(event.reason));
window.addEventListener('DOMContentLoaded', () => start().catch(report));
