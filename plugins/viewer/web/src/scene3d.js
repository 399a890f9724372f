// The 3D view (vtk.js): the skull's surface, the brain's boundary at its
// current node positions, the device, the proxy and the contact point, and
// the force on the hand as an arrow.
import '@kitware/vtk.js/Rendering/Profiles/Geometry';
import vtkGenericRenderWindow from '@kitware/vtk.js/Rendering/Misc/GenericRenderWindow';
import vtkActor from '@kitware/vtk.js/Rendering/Core/Actor';
import vtkMapper from '@kitware/vtk.js/Rendering/Core/Mapper';
import vtkPolyData from '@kitware/vtk.js/Common/DataModel/PolyData';
import vtkSphereSource from '@kitware/vtk.js/Filters/Sources/SphereSource';
import vtkArrowSource from '@kitware/vtk.js/Filters/Sources/ArrowSource';
import vtkDataArray from '@kitware/vtk.js/Common/Core/DataArray';
import { tetBoundary } from './tetSurface.js';
import { meshColours, skullColours } from './colouring.js';

// Colours (RGB, 0..1); the browser test looks for them.
export const kColours = {
  background: [0.12, 0.13, 0.16],
  skull: [0.91, 0.87, 0.76],
  brain: [0.9, 0.55, 0.6],
  surface: [0.7, 0.75, 0.8],
  proxy: [0.2, 0.45, 0.95],
  device: [0.3, 0.85, 0.35],
  force: [0.95, 0.25, 0.15],
  contact: [1.0, 0.85, 0.1],
};

function surfaceActor(colour) {
  const polyData = vtkPolyData.newInstance();
  const mapper = vtkMapper.newInstance({ scalarVisibility: false });
  mapper.setInputData(polyData);
  const actor = vtkActor.newInstance();
  actor.setMapper(mapper);
  actor.getProperty().setColor(...colour);
  actor.getProperty().setDiffuse(0.85);
  actor.getProperty().setAmbient(0.15);
  actor.setVisibility(false);
  return { polyData, actor };
}

function sourceActor(source, colour) {
  const mapper = vtkMapper.newInstance({ scalarVisibility: false });
  mapper.setInputConnection(source.getOutputPort());
  const actor = vtkActor.newInstance();
  actor.setMapper(mapper);
  actor.getProperty().setColor(...colour);
  actor.setVisibility(false);
  return actor;
}

// A column-major matrix taking the unit arrow along +x (from 0 to 1) to
// `from` + `vector`, `width` mm thick.
function arrowMatrix(from, vector, width) {
  const length = Math.hypot(...vector);
  const x = vector.map((v) => v / length);
  const helper = Math.abs(x[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  let y = cross(x, helper);
  const norm = Math.hypot(...y);
  y = y.map((v) => v / norm);
  const z = cross(x, y);
  return [
    ...x.map((v) => v * length), 0,
    ...y.map((v) => v * width), 0,
    ...z.map((v) => v * width), 0,
    ...from, 1,
  ];
}

export class Scene3d {
  constructor(container) {
    this.view = vtkGenericRenderWindow.newInstance({ background: kColours.background, listenWindowResize: true });
    this.view.setContainer(container);
    this.pixelScale = 1;  // drawn pixels per CSS pixel (and device pixel ratio)
    this.view.resize();
    this.renderer = this.view.getRenderer();
    this.renderWindow = this.view.getRenderWindow();
    this.parts = new Map();  // part name -> its drawing
    this.hidden = new Set();  // part names the user hid
    this.opacity = new Map();  // part name -> opacity (0..1)
    this.levels = new Map();  // block part name -> the level drawn
    this.cameraSet = false;
    this.forceScale = 10;  // mm of arrow per N; set from the run's largest force
    this.colouring = new Map();  // part name -> {mode, ranges}: what it is coloured by
    this.volume = null;  // the skull's SkullVolume, once loaded
    this.time = 0;       // s, the time shown (the skull's cuts up to it)
    this.end = 0;        // s, the run's end (the cut times' colour range)
  }

  // Colours part `name` by `mode` (colouring.js; null or a plain mode: its
  // own colour); `ranges`: a mesh's ranges of each quantity.
  setColouring(name, mode, ranges = {}) {
    this.colouring.set(name, { mode, ranges });
    for (const part of this.partsNamed(name)) this.applyColours(part);
  }

  // The time shown: a skull coloured by its cuts shows those made by then.
  setTime(t) {
    if (t === this.time) return;
    this.time = t;
    for (const part of this.parts.values())
      if (part.pieces && this.colouring.get(part.name)?.mode === 'cut') this.applyColours(part);
  }

  applyColours(part) {
    if (!part.polyData) return;
    const colouring = this.colouring.get(part.name);
    let colours = null;
    if (colouring && part.file) colours = meshColours(part.file, colouring.mode, part.faceCells, colouring.ranges);
    else if (colouring && part.pieces)
      colours = { bytes: skullColours(part.pieces, colouring.mode, this.volume, this.time, this.end, kColours.skull), cells: false };
    const mapper = part.actor.getMapper();
    if (!colours || !colours.bytes) {
      mapper.setScalarVisibility(false);
      part.coloured = false;
      return;
    }
    const scalars = vtkDataArray.newInstance({ name: 'colour', numberOfComponents: 3, values: colours.bytes });
    part.polyData.getPointData().setScalars(colours.cells ? null : scalars);
    part.polyData.getCellData().setScalars(colours.cells ? scalars : null);
    mapper.setColorModeToDirectScalars();
    if (colours.cells) mapper.setScalarModeToUseCellData();
    else mapper.setScalarModeToUsePointData();
    mapper.setScalarVisibility(true);
    part.polyData.modified();
    part.coloured = true;
  }

  setForceScale(maxForce, sceneSize) {
    if (maxForce > 0) this.forceScale = (0.2 * sceneSize) / maxForce;
  }

  // Draws part `name` of kind `kind` from `files` (one file, or a .vtm's
  // blocks) at `key` (a state: nothing is rebuilt when it did not change).
  // Block parts (a skull) have two levels of detail, 'moving' and 'still',
  // each with its own actor: switching between them uploads nothing.
  show(name, kind, key, files, level = 'moving') {
    const id = kind === 'blocks' && level === 'still' ? `${name}@still` : name;
    let part = this.parts.get(id);
    if (!part) {
      part = this.createPart(kind, name);
      part.name = name;
      if (kind === 'blocks') part.level = level;
      this.parts.set(id, part);
      if (this.opacity.has(name)) this.setOpacity(name, this.opacity.get(name));
    }
    if (kind === 'blocks') this.levels.set(name, level);
    if (part.key !== key) {
      part.key = key;
      if (kind === 'mesh') this.updateMesh(part, files[0]);
      else if (kind === 'blocks') this.updateBlocks(part, files);
      else if (kind === 'tool') this.updateTool(part, files[0]);
      else this.updateSurface(part, files[0]);
    }
    for (const other of this.partsNamed(name)) this.applyVisibility(other);
  }

  partsNamed(name) {
    return [...this.parts.values()].filter((part) => part.name === name);
  }

  // `name`: the tool's true shape (toolshape) takes the proxy's colour.
  createPart(kind, name) {
    if (kind === 'tool') {
      const proxySource = vtkSphereSource.newInstance({ thetaResolution: 24, phiResolution: 16 });
      const deviceSource = vtkSphereSource.newInstance({ thetaResolution: 16, phiResolution: 12 });
      const arrowSource = vtkArrowSource.newInstance({ tipLength: 0.3, tipRadius: 0.25, shaftRadius: 0.1 });
      arrowSource.update();
      // The arrow from 0 to 1 along x (its source centres it).
      const arrow = arrowSource.getOutputData();
      const arrowPoints = arrow.getPoints().getData();
      for (let i = 0; i < arrowPoints.length; i += 3) arrowPoints[i] += 0.5;
      const arrowMapper = vtkMapper.newInstance({ scalarVisibility: false });
      arrowMapper.setInputData(arrow);
      const arrowActor = vtkActor.newInstance();
      arrowActor.setMapper(arrowMapper);
      arrowActor.getProperty().setColor(...kColours.force);
      arrowActor.setVisibility(false);
      const contactSource = vtkSphereSource.newInstance({ thetaResolution: 12, phiResolution: 8 });
      const part = {
        proxySource,
        deviceSource,
        contactSource,
        proxy: sourceActor(proxySource, kColours.proxy),
        device: sourceActor(deviceSource, kColours.device),
        contact: sourceActor(contactSource, kColours.contact),
        arrow: arrowActor,
      };
      for (const actor of [part.proxy, part.device, part.contact, part.arrow]) this.renderer.addActor(actor);
      return part;
    }
    const colour = kind === 'mesh' ? kColours.brain : kind === 'blocks' ? kColours.skull
      : name === 'toolshape' ? kColours.proxy : kColours.surface;
    const part = surfaceActor(colour);
    this.renderer.addActor(part.actor);
    return part;
  }

  updateMesh(part, file) {
    const points = file.array('Points');
    const topology = `${file.count('NumberOfPoints')}/${file.count('NumberOfCells')}`;
    if (part.topology !== topology) {
      part.topology = topology;
      const { polys, faceCells } = tetBoundary(points, file.array('Cells', 'connectivity'), file.array('Cells', 'offsets'),
                                               file.array('Cells', 'types'));
      part.polyData.getPolys().setData(polys, 1);
      part.faceCells = faceCells;
    }
    part.polyData.getPoints().setData(points, 3);
    part.polyData.modified();
    part.hasData = true;
    part.file = file;
    this.applyColours(part);
    this.applyVisibility(part);
  }

  // A polygonal surface: its triangles (polygons of 3 corners) only.
  static triangles(file, cache) {
    if (file.surface) return file.surface();
    let found = cache && cache.get(file.name);
    if (found) return found;
    const points = file.array('Points') || new Float32Array(0);
    const connectivity = file.array('Polys', 'connectivity') || new Int32Array(0);
    const offsets = file.array('Polys', 'offsets') || new Int32Array(0);
    const triangles = [];
    let start = 0;
    for (const end of offsets) {
      if (end - start === 3) triangles.push(connectivity[start], connectivity[start + 1], connectivity[start + 2]);
      start = end;
    }
    found = { points, triangles: Uint32Array.from(triangles) };
    if (cache) cache.set(file.name, found);
    return found;
  }

  updateSurface(part, file) {
    const { points, triangles } = Scene3d.triangles(file, null);
    this.setTriangles(part, [{ points, triangles }]);
  }

  updateBlocks(part, files) {
    part.blockCache = part.blockCache || new Map();
    this.setTriangles(part, files.map((file) => Scene3d.triangles(file, part.blockCache)));
  }

  setTriangles(part, pieces) {
    let pointCount = 0;
    let triangleCount = 0;
    for (const piece of pieces) {
      pointCount += piece.points.length / 3;
      triangleCount += piece.triangles.length / 3;
    }
    const points = new Float32Array(pointCount * 3);
    const polys = new Uint32Array(triangleCount * 4);
    let p = 0;
    let t = 0;
    for (const piece of pieces) {
      points.set(piece.points, p * 3);
      const triangles = piece.triangles;
      for (let i = 0; i < triangles.length; i += 3, ++t) {
        polys[4 * t] = 3;
        polys[4 * t + 1] = triangles[i] + p;
        polys[4 * t + 2] = triangles[i + 1] + p;
        polys[4 * t + 3] = triangles[i + 2] + p;
      }
      p += piece.points.length / 3;
    }
    part.polyData.getPoints().setData(points, 3);
    part.polyData.getPolys().setData(polys, 1);
    part.polyData.modified();
    part.hasData = triangleCount > 0;
    part.pieces = pieces;
    this.applyColours(part);
    this.applyVisibility(part);
    part.triangleCount = triangleCount;
  }

  updateTool(part, file) {
    const points = file.array('Points');
    const force = file.array('PointData', 'force');
    const radius = file.array('PointData', 'radius');
    if (!points || points.length < 6) return;
    // A third point: the contact point (in contact only).
    this.setToolPose(part, Array.from(points.subarray(0, 3)), Array.from(points.subarray(3, 6)),
                     force ? Array.from(force.subarray(3, 6)) : [0, 0, 0], radius ? radius[1] : 0,
                     points.length >= 9 ? Array.from(points.subarray(6, 9)) : null);
  }

  // The device and proxy (mm), the force on the hand (N), the tool's radius
  // (mm; 0: unknown, drawn 2.5 mm) and the contact point (mm, or null).
  setToolPose(part, device, proxy, force, radius, contact) {
    const toolRadius = radius > 0 ? radius : 2.5;
    part.hasContact = Boolean(contact);
    if (contact) {
      part.contactSource.setCenter(...contact);
      part.contactSource.setRadius(0.3 * toolRadius);
    }
    part.proxySource.setCenter(...proxy);
    part.proxySource.setRadius(toolRadius);
    part.deviceSource.setCenter(...device);
    part.deviceSource.setRadius(0.4 * toolRadius);
    part.hasTool = true;
    const length = Math.hypot(...force) * this.forceScale;
    if (length > 1e-3) {
      part.arrow.setUserMatrix(arrowMatrix(proxy, force.map((v) => v * this.forceScale), Math.max(toolRadius, 0.2 * length)));
      part.hasArrow = true;
    } else {
      part.hasArrow = false;
    }
    this.applyVisibility(part);
  }

  // The part named `name`, made on first use (the live view has no files).
  partFor(name, kind) {
    let part = this.parts.get(name);
    if (!part) {
      part = this.createPart(kind, name);
      part.name = name;
      this.parts.set(name, part);
      if (this.opacity.has(name)) this.setOpacity(name, this.opacity.get(name));
    }
    return part;
  }

  // A tetrahedral mesh's nodes (Float32Array, mm); `corners` (4 a
  // tetrahedron) when its topology is new.
  setMeshNodes(part, points, corners) {
    if (corners) {
      const tets = corners.length / 4;
      const offsets = new Int32Array(tets);
      for (let i = 0; i < tets; ++i) offsets[i] = 4 * (i + 1);
      part.polyData.getPolys().setData(tetBoundary(points, corners, offsets, new Uint8Array(tets).fill(10)).polys, 1);
    }
    part.polyData.getPoints().setData(points, 3);
    part.polyData.modified();
    part.hasData = part.polyData.getPolys().getNumberOfCells() > 0;
    this.applyVisibility(part);
  }

  // Surfaces [{points, triangles}] drawn as one.
  setPieces(part, pieces) {
    this.setTriangles(part, pieces);
  }

  // The actors of a part, each with whether it has something to draw.
  static actorsOf(part) {
    if (part.proxy) {
      return [[part.proxy, part.hasTool], [part.device, part.hasTool], [part.contact, part.hasContact],
              [part.arrow, part.hasArrow]];
    }
    return [[part.actor, part.hasData]];
  }

  applyVisibility(part) {
    const shown = !this.hidden.has(part.name) && (part.level === undefined || this.levels.get(part.name) === part.level);
    for (const [actor, has] of Scene3d.actorsOf(part)) actor.setVisibility(shown && Boolean(has));
  }

  setHidden(name, hidden) {
    if (hidden) this.hidden.add(name);
    else this.hidden.delete(name);
    for (const part of this.partsNamed(name)) this.applyVisibility(part);
  }

  // A translucent surface draws only the faces turned to the camera: seen
  // through, the far sides of folds and slivers would shine as flecks.
  setOpacity(name, opacity) {
    this.opacity.set(name, opacity);
    for (const part of this.partsNamed(name))
      for (const [actor] of Scene3d.actorsOf(part)) {
        actor.getProperty().setOpacity(opacity);
        actor.getProperty().setBackfaceCulling(opacity < 1);
      }
  }

  resetCameraOnce() {
    if (this.cameraSet) return;
    this.cameraSet = true;
    const camera = this.renderer.getActiveCamera();
    // From the front and a little above: +y is posterior and +z superior
    // in the scanner's frame of the phantoms.
    camera.setPosition(0.8, -1, 0.6);
    camera.setFocalPoint(0, 0, 0);
    camera.setViewUp(0, 0, 1);
    this.renderer.resetCamera();
    this.renderer.getActiveCamera().zoom(1.4);  // resetCamera leaves a wide margin
  }

  // Draws at `scale` of the display's pixels (the canvas is stretched): a
  // software renderer shades a quarter of the pixels at 0.5.
  setPixelScale(scale) {
    this.pixelScale = scale;
    const box = this.view.getContainer().getBoundingClientRect();
    const ratio = (window.devicePixelRatio || 1) * scale;
    this.view.getApiSpecificRenderWindow().setSize(Math.max(1, Math.floor(box.width * ratio)),
                                                   Math.max(1, Math.floor(box.height * ratio)));
  }

  render() {
    this.renderWindow.render();
  }

  // Of the level drawn.
  triangleCount(name) {
    const part = this.partsNamed(name).find((p) => p.level === undefined || this.levels.get(name) === p.level);
    if (!part) return 0;
    if (part.triangleCount) return part.triangleCount;
    return part.polyData ? part.polyData.getPolys().getNumberOfCells() : 0;
  }
}
