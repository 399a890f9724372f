// The CT itself, drawn as a volume (vtk.js ray casting) from the skull's
// packed volume (skullVolume.js): air transparent, bone from the isovalue up
// ever more opaque and whiter, and the voxels the drill has cut by the time
// shown drawn in orange where the bone was, so that the drilled region reads
// at a glance. Off by default: a software renderer casts rays slowly.
import '@kitware/vtk.js/Rendering/Profiles/Volume';
import vtkVolume from '@kitware/vtk.js/Rendering/Core/Volume';
import vtkVolumeMapper from '@kitware/vtk.js/Rendering/Core/VolumeMapper';
import vtkImageData from '@kitware/vtk.js/Common/DataModel/ImageData';
import vtkDataArray from '@kitware/vtk.js/Common/Core/DataArray';
import vtkColorTransferFunction from '@kitware/vtk.js/Rendering/Core/ColorTransferFunction';
import vtkPiecewiseFunction from '@kitware/vtk.js/Common/DataModel/PiecewiseFunction';
import { densityRange } from './colouring.js';

// The cut colour (RGB 0..1); the browser test looks for it.
export const kCutColour = [1.0, 0.55, 0.1];

export class CtVolume {
  constructor(renderer, volume) {
    this.volume = volume;
    const count = volume.codes.length;
    this.densities = new Float32Array(count);
    for (let i = 0; i < count; ++i) this.densities[i] = volume.offset + volume.scale * volume.codes[i];
    const [iso, high] = densityRange(volume);
    // Cut voxels take a value below the air's: the transfer functions draw it orange.
    this.cutValue = volume.range[0] - (high - volume.range[0]);
    this.values = this.densities.slice();
    this.image = vtkImageData.newInstance();
    this.image.setDimensions(...volume.dims);
    this.image.setSpacing(...volume.spacing);
    this.image.setOrigin(...volume.origin);
    this.scalars = vtkDataArray.newInstance({ name: 'density', numberOfComponents: 1, values: this.values });
    this.image.getPointData().setScalars(this.scalars);
    this.mapper = vtkVolumeMapper.newInstance();
    this.mapper.setInputData(this.image);
    this.mapper.setSampleDistance(0.7 * Math.min(...volume.spacing));
    this.actor = vtkVolume.newInstance();
    this.actor.setMapper(this.mapper);
    const colour = vtkColorTransferFunction.newInstance();
    const halfway = 0.5 * (this.cutValue + volume.range[0]);
    colour.addRGBPoint(this.cutValue, ...kCutColour);
    colour.addRGBPoint(halfway, ...kCutColour);
    colour.addRGBPoint(iso, 0.75, 0.68, 0.55);
    colour.addRGBPoint(high, 1.0, 0.98, 0.94);
    const opacity = vtkPiecewiseFunction.newInstance();
    opacity.addPoint(this.cutValue, 0.6);
    opacity.addPoint(halfway, 0.6);
    opacity.addPoint(halfway + 1e-3 * (high - this.cutValue), 0);
    opacity.addPoint(iso, 0);
    opacity.addPoint(iso + 0.1 * (high - iso), 0.08);
    opacity.addPoint(high, 0.5);
    this.actor.getProperty().setRGBTransferFunction(0, colour);
    this.actor.getProperty().setScalarOpacity(0, opacity);
    this.actor.getProperty().setScalarOpacityUnitDistance(0, 2 * Math.max(...volume.spacing));
    this.actor.getProperty().setInterpolationTypeToLinear();
    this.actor.getProperty().setShade(true);
    this.actor.getProperty().setAmbient(0.3);
    this.actor.getProperty().setDiffuse(0.7);
    this.actor.setVisibility(false);
    renderer.addVolume(this.actor);
    this.shownCuts = 0;  // removed voxels applied (volume.removedOrder is in time order)
    this.cutVoxels = 0;
  }

  setVisible(visible) {
    this.actor.setVisibility(visible);
  }

  // The cuts made by time t (s): voxels cut by then take the cut value.
  setTime(t) {
    const order = this.volume.removedOrder;
    const before = this.shownCuts;
    let n = 0;
    while (n < order.length && order[n].t <= t) ++n;
    if (n === before) return;
    for (let i = Math.min(n, before); i < Math.max(n, before); ++i) {
      const voxel = order[i].voxel;
      this.values[voxel] = i < n ? this.cutValue : this.densities[voxel];
    }
    this.shownCuts = n;
    this.cutVoxels = n;
    this.scalars.modified();
    this.image.modified();
  }
}
