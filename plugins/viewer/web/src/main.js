// The viewer of a trephine run: the 3D view, a time slider, a play button and
// the plots. URL parameters (for links and tests): t=SECONDS starts there,
// play=1 starts playing, speed=X plays X times real time, hide=a,b hides
// those parts, opacity=X draws the skull at that opacity (0..1), scale=X
// draws at X of the display's pixels, playScale=X while playing (0.35).
// window.trephineViewer reports its state: ready (the first frame drawn),
// openSeconds, time, frame, framesDrawn, triangles per part, levels (of
// the block parts: 'moving' or 'still'), renderer,
// errors; and seek(t).
import { RunData } from './runData.js';
import { Scene3d } from './scene3d.js';
import { Plots } from './plots.js';
import { startLive } from './live.js';

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

function rendererName() {
  const gl = document.createElement('canvas').getContext('webgl2');
  if (!gl) return 'no WebGL2';
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}

// A checkbox per part, and the skull's opacity (to see the brain inside).
function addPartToggles(manifest, scene, parameters) {
  const toggles = document.getElementById('parts');
  const hidden = new Set((parameters.get('hide') || '').split(',').filter(Boolean));
  for (const part of manifest.parts) {
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = !hidden.has(part.name);
    scene.setHidden(part.name, !box.checked);
    box.addEventListener('change', () => {
      scene.setHidden(part.name, !box.checked);
      scene.render();
    });
    label.append(box, ` ${part.name}`);
    toggles.append(label);
    if (part.kind === 'blocks') {
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
      toggles.append(opacity);
    }
  }
}

async function start() {
  const manifest = window.trephineRun;
  if (!manifest) throw new Error('data/manifest.js is missing: write the viewer with trephine view RUN_DIR');
  document.getElementById('title').textContent = manifest.name;
  status.renderer = rendererName();
  const scene = new Scene3d(document.getElementById('view'));
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

  const plots = new Plots(document.getElementById('plots'), manifest.plots, end, (t) => seek(t));
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
    const index = data.frameAt(time);
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

  addPartToggles(manifest, scene, parameters);
  speed = Number(parameters.get('speed') || 1);
  if (fullScale !== 1) scene.setPixelScale(fullScale);
  showTime(Number(parameters.get('t') || 0));
  if (parameters.get('play') === '1') setPlaying(true);
}

window.addEventListener('error', (event) => report(event.error || event.message));
window.addEventListener('unhandledrejection', (event) => report(event.reason));
window.addEventListener('DOMContentLoaded', () => start().catch(report));
