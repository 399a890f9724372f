// Finding one's way in the 3D view: the mouse (left turns about the focal
// point, shift+left or middle pans, the wheel or right drag zooms toward the
// cursor), an axes triad and a scale bar drawn over the view, the standard
// views of a head (anterior, posterior, left, right, superior) and the view
// the viewer opened with (reset), and a clipping plane across the skull and
// the brain. The scene's axes are the scanner's LPS: +x left, +y posterior,
// +z superior.
import vtkInteractorStyleManipulator from '@kitware/vtk.js/Interaction/Style/InteractorStyleManipulator';
import vtkMouseCameraTrackballRotateManipulator from '@kitware/vtk.js/Interaction/Manipulators/MouseCameraTrackballRotateManipulator';
import vtkMouseCameraTrackballPanManipulator from '@kitware/vtk.js/Interaction/Manipulators/MouseCameraTrackballPanManipulator';
import vtkMouseCameraTrackballZoomToMouseManipulator from '@kitware/vtk.js/Interaction/Manipulators/MouseCameraTrackballZoomToMouseManipulator';
import vtkPlane from '@kitware/vtk.js/Common/DataModel/Plane';

// Where the camera looks from (a unit direction from the focal point) and its up.
export const kStandardViews = {
  anterior: { from: [0, -1, 0], up: [0, 0, 1] },
  posterior: { from: [0, 1, 0], up: [0, 0, 1] },
  left: { from: [1, 0, 0], up: [0, 0, 1] },
  right: { from: [-1, 0, 0], up: [0, 0, 1] },
  superior: { from: [0, 0, 1], up: [0, -1, 0] },
};
const kAxes = [
  { label: 'x (L)', colour: '#e8483c', direction: [1, 0, 0] },
  { label: 'y (P)', colour: '#4fc24f', direction: [0, 1, 0] },
  { label: 'z (S)', colour: '#4f8ff5', direction: [0, 0, 1] },
];

const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => {
  const n = Math.hypot(...a) || 1;
  return a.map((v) => v / n);
};

export class ViewControls {
  constructor(scene, container) {
    this.scene = scene;
    this.container = container;
    const interactor = scene.view.getInteractor();
    const style = vtkInteractorStyleManipulator.newInstance();
    style.addMouseManipulator(vtkMouseCameraTrackballRotateManipulator.newInstance({ button: 1, useFocalPointAsCenterOfRotation: true }));
    style.addMouseManipulator(vtkMouseCameraTrackballPanManipulator.newInstance({ button: 1, shift: true }));
    style.addMouseManipulator(vtkMouseCameraTrackballPanManipulator.newInstance({ button: 2 }));
    style.addMouseManipulator(vtkMouseCameraTrackballZoomToMouseManipulator.newInstance({ button: 3 }));
    style.addMouseManipulator(vtkMouseCameraTrackballZoomToMouseManipulator.newInstance({ scrollEnabled: true, dragEnabled: false }));
    interactor.setInteractorStyle(style);

    this.triad = document.createElement('canvas');
    this.triad.className = 'triad';
    this.triad.width = 120;
    this.triad.height = 120;
    this.scaleBar = document.createElement('div');
    this.scaleBar.className = 'scale-bar';
    this.scaleBar.title = 'Length at the focal point (the centre of the view)';
    container.append(this.triad, this.scaleBar);
    this.home = null;  // the opening view: {position, focalPoint, viewUp}
    this.state = { triad: {}, scaleBar: { mm: 0, pixels: 0 }, view: 'opening' };
    const camera = scene.renderer.getActiveCamera();
    camera.onModified(() => this.scheduleOverlay());
    // The view's size follows its box (the toolbars above it wrap and grow).
    new ResizeObserver(() => {
      scene.setPixelScale(scene.pixelScale);
      scene.render();
      this.scheduleOverlay();
    }).observe(container);

    this.clipPlane = vtkPlane.newInstance({ normal: [1, 0, 0], origin: [0, 0, 0] });
    this.clipping = null;  // {axis, fraction, flip}
  }

  // Keeps the view the viewer opened with, for reset().
  rememberHome() {
    const camera = this.scene.renderer.getActiveCamera();
    this.home = { position: camera.getPosition(), focalPoint: camera.getFocalPoint(), viewUp: camera.getViewUp() };
    this.scheduleOverlay();
  }

  reset() {
    if (!this.home) return;
    const camera = this.scene.renderer.getActiveCamera();
    camera.setPosition(...this.home.position);
    camera.setFocalPoint(...this.home.focalPoint);
    camera.setViewUp(...this.home.viewUp);
    this.scene.renderer.resetCameraClippingRange();
    this.state.view = 'opening';
    this.scene.render();
  }

  // One of kStandardViews, about the opening view's focal point and at its distance.
  standardView(name) {
    const view = kStandardViews[name];
    if (!view || !this.home) return;
    const camera = this.scene.renderer.getActiveCamera();
    const focal = this.home.focalPoint;
    const distance = Math.hypot(...this.home.position.map((v, a) => v - focal[a]));
    camera.setFocalPoint(...focal);
    camera.setPosition(...focal.map((v, a) => v + distance * view.from[a]));
    camera.setViewUp(...view.up);
    this.scene.renderer.resetCameraClippingRange();
    this.state.view = name;
    this.scene.render();
  }

  // A plane across the surfaces (not the tools): normal to `axis` (0, 1, 2;
  // null: none) at `fraction` of the scene's extent along it, keeping the
  // side beyond it (or before it with `flip`).
  setClipping(axis, fraction, flip) {
    this.clipping = axis === null ? null : { axis, fraction, flip };
    const bounds = this.bounds();
    if (this.clipping) {
      const origin = [0, 0, 0];
      origin[axis] = bounds[2 * axis] + fraction * (bounds[2 * axis + 1] - bounds[2 * axis]);
      const normal = [0, 0, 0];
      normal[axis] = flip ? -1 : 1;
      this.clipPlane.setOrigin(...origin);
      this.clipPlane.setNormal(...normal);
    }
    for (const part of this.scene.parts.values()) {
      if (!part.actor) continue;  // tools are never clipped
      const mapper = part.actor.getMapper();
      mapper.removeAllClippingPlanes();
      if (this.clipping) mapper.addClippingPlane(this.clipPlane);
    }
    this.scene.render();
  }

  // The box of every part with data, shown or hidden (hiding one keeps the frame).
  bounds() {
    if (!this.sceneBounds) {
      const b = this.scene.renderer.computeVisiblePropBounds();
      if (b[0] <= b[1]) this.sceneBounds = b;
      else return [-1, 1, -1, 1, -1, 1];
    }
    return this.sceneBounds;
  }

  scheduleOverlay() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.drawOverlay();
    });
  }

  // The triad (the world axes as the camera sees them) and the scale bar.
  drawOverlay() {
    const camera = this.scene.renderer.getActiveCamera();
    const position = camera.getPosition();
    const focal = camera.getFocalPoint();
    const forward = unit(focal.map((v, a) => v - position[a]));
    const right = unit(cross(forward, camera.getViewUp()));
    const up = cross(right, forward);
    const g = this.triad.getContext('2d');
    const size = this.triad.width;
    g.clearRect(0, 0, size, size);
    const centre = size / 2;
    const length = size * 0.27;
    g.font = 'bold 11px sans-serif';
    g.lineWidth = 2.5;
    // Far axes first, so the nearest is drawn over them.
    const axes = kAxes.map((axis) => ({ ...axis, x: dot(axis.direction, right), y: dot(axis.direction, up), depth: dot(axis.direction, forward) }));
    axes.sort((a, b) => b.depth - a.depth);
    for (const axis of axes) {
      const endX = centre + length * axis.x;
      const endY = centre - length * axis.y;
      g.strokeStyle = axis.colour;
      g.fillStyle = axis.colour;
      g.beginPath();
      g.moveTo(centre, centre);
      g.lineTo(endX, endY);
      g.stroke();
      // The label beyond the axis' end, kept inside the canvas.
      const textWidth = g.measureText(axis.label).width;
      const labelX = Math.min(Math.max(axis.x < 0 ? endX - 4 - textWidth : endX + 4, 0), size - textWidth);
      const labelY = Math.min(Math.max(axis.y < 0 ? endY + 12 : endY - 4, 10), size - 2);
      g.fillText(axis.label, labelX, labelY);
      this.state.triad[axis.label] = [axis.x, axis.y];
    }
    // mm per CSS pixel at the focal point.
    const box = this.container.getBoundingClientRect();
    const distance = Math.hypot(...focal.map((v, a) => v - position[a]));
    const heightMm = camera.getParallelProjection()
      ? 2 * camera.getParallelScale()
      : 2 * distance * Math.tan((camera.getViewAngle() * Math.PI) / 360);
    const mmPerPixel = heightMm / Math.max(box.height, 1);
    const target = 120 * mmPerPixel;  // about 120 pixels long
    const power = 10 ** Math.floor(Math.log10(target));
    const mm = [1, 2, 5, 10].map((m) => m * power).filter((v) => v <= target).pop() || power;
    const pixels = mm / mmPerPixel;
    this.scaleBar.style.width = `${pixels.toFixed(1)}px`;
    this.scaleBar.textContent = `${mm >= 1 ? mm.toFixed(0) : mm.toPrecision(1)} mm`;
    this.state.scaleBar = { mm, pixels, mmPerPixel };
  }
}
