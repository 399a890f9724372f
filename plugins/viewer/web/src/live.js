// The live view: the viewer that `trephine run --realtime --view PORT`
// serves, fed by the run over a WebSocket at /stream (the messages are
// described in plugins/viewer/LiveStream.h). It draws each tool message, the
// brain's nodes as they move and the skull's blocks as the drill changes
// them, and plots the force and penetration of the last 10 s.
const kPlotSeconds = 10;

export function startLive(manifest, scene, plots, status, report) {
  const kinds = Object.fromEntries(manifest.parts.map((part) => [part.name, part.kind]));
  const brain = Object.keys(kinds).find((name) => kinds[name] === 'mesh');
  const skull = Object.keys(kinds).find((name) => kinds[name] === 'blocks');
  const tool = Object.keys(kinds).find((name) => kinds[name] === 'tool');
  const blocks = new Map();  // block -> {points, triangles}
  let corners = null;        // the brain's tetrahedra, until its first nodes
  let brainSeen = false;
  let skullDirty = false;
  let dirty = false;
  let time = 0;
  const history = { t: [], force: [], penetration: [] };
  plots.plots = history;

  const draw = () => {
    if (!dirty || status.frozen) return;  // frozen: held for a screenshot
    dirty = false;
    if (skullDirty && skull) {
      skullDirty = false;
      scene.setPieces(scene.partFor(skull, 'blocks'), [...blocks.values()]);
    }
    // The camera fits the patient once it is there (the skull's blocks and
    // the brain's nodes come first on connecting, then the tool).
    if (!scene.cameraSet && (!skull || blocks.size > 0) && (!brain || brainSeen)) scene.resetCameraOnce();
    scene.render();
    status.framesDrawn += 1;
    status.time = time;
    for (const name of Object.keys(kinds)) status.triangles[name] = scene.triangleCount(name);
    if (!status.ready && status.framesDrawn > 0 && tool && status.toolMessages > 0) {
      status.ready = true;
      status.openSeconds = performance.now() / 1000;
    }
    document.getElementById('clock').textContent = `${time.toFixed(3)} s`;
    // The last kPlotSeconds, or the run so far.
    plots.start = Math.max(0, time - kPlotSeconds);
    plots.end = Math.max(time, 1e-3);
    plots.curves = null;  // new samples: draw the curves again
    plots.setTime(time);
  };
  const frame = () => {
    draw();
    requestAnimationFrame(frame);
  };
  requestAnimationFrame(frame);
  // Drawing needs the page's frames; a hidden page gets none, so also draw
  // from a timer at most 30 times a second.
  setInterval(draw, 33);

  const onTool = (view) => {
    time = view.getFloat64(8, true);
    const vec = (at) => [0, 1, 2].map((k) => view.getFloat32(at + 4 * k, true));
    const device = vec(16);
    const proxy = vec(28);
    const force = vec(40);
    const radius = view.getFloat32(52, true);
    const penetration = view.getFloat32(56, true);
    const contact = view.getUint32(4, true) ? vec(60) : null;
    if (tool) scene.setToolPose(scene.partFor(tool, 'tool'), device, proxy, force, radius, contact);
    status.toolMessages = (status.toolMessages || 0) + 1;
    history.t.push(time);
    history.force.push(Math.hypot(...force));
    history.penetration.push(penetration);
    while (history.t.length && history.t[0] < time - kPlotSeconds) {
      history.t.shift();
      history.force.shift();
      history.penetration.shift();
    }
    dirty = true;
  };
  const onNodes = (buffer) => {
    const view = new DataView(buffer);
    const count = view.getUint32(4, true);
    const points = new Float32Array(buffer.slice(16, 16 + 12 * count));
    if (brain) scene.setMeshNodes(scene.partFor(brain, 'mesh'), points, corners);
    corners = null;
    brainSeen = true;
    dirty = true;
  };
  const onCells = (buffer) => {
    const view = new DataView(buffer);
    const count = view.getUint32(4, true);
    corners = new Int32Array(buffer.slice(8, 8 + 16 * count));
  };
  const onBlock = (buffer) => {
    const view = new DataView(buffer);
    const block = view.getUint32(4, true);
    const points = view.getUint32(8, true);
    const triangles = view.getUint32(12, true);
    if (triangles === 0) blocks.delete(block);
    else {
      blocks.set(block, {
        points: new Float32Array(buffer.slice(16, 16 + 12 * points)),
        triangles: new Uint32Array(buffer.slice(16 + 12 * points, 16 + 12 * points + 12 * triangles)),
      });
    }
    skullDirty = true;
    dirty = true;
  };

  // The tool in hand in its true shape (a burr on its shaft), in the world.
  const toolShape = Object.keys(kinds).find((name) => name === 'toolshape');
  const onToolSurface = (buffer) => {
    const view = new DataView(buffer);
    const points = view.getUint32(4, true);
    const triangles = view.getUint32(8, true);
    if (!toolShape) return;
    scene.setPieces(scene.partFor(toolShape, 'polydata'), [{
      points: new Float32Array(buffer.slice(12, 12 + 12 * points)),
      triangles: new Uint32Array(buffer.slice(12 + 12 * points, 12 + 12 * points + 12 * triangles)),
    }]);
    dirty = true;
  };

  const socket = new WebSocket(`ws://${window.location.host}/stream`);
  socket.binaryType = 'arraybuffer';
  socket.onmessage = (event) => {
    if (typeof event.data === 'string') return;  // text: none yet
    const buffer = event.data;
    const view = new DataView(buffer);
    const type = view.getUint32(0, true);
    if (type === 1) onTool(view);
    else if (type === 2) onNodes(buffer);
    else if (type === 3) onCells(buffer);
    else if (type === 4) onBlock(buffer);
    else if (type === 5) onToolSurface(buffer);
    else report(new Error(`live view: a message of unknown type ${type}`));
  };
  socket.onclose = () => {
    status.closed = true;
    document.getElementById('message').textContent = 'the run has ended (its outputs are in its run directory)';
  };
  socket.onerror = () => report(new Error(`live view: the connection to ws://${window.location.host}/stream failed`));
}
