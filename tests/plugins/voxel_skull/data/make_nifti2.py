#!/usr/bin/env python3
"""Writes the NIfTI-2 files VolumeIoTest reads, with nibabel (Debian's
python3-nibabel), a writer independent of the project's reader. Only needed
to regenerate them:

    python3 tests/plugins/voxel_skull/data/make_nifti2.py

The samples are VolumeIoTest's ramp, 100 k + 10 j + i - 7 at stored index
(i, j, k), on a 3 x 4 x 5 grid.
"""
import os

import nibabel as nib
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
i, j, k = np.meshgrid(np.arange(3), np.arange(4), np.arange(5), indexing="ij")
ramp = 100 * k + 10 * j + i - 7

# int16, little endian, an sform that permutes and flips the axes (stored
# axis 0 along -y at 0.5 mm, axis 1 along +z at 0.75 mm, axis 2 along +x at
# 2 mm), origin (10, 20, -30) mm.
sform = np.array([[0, 0, 2, 10], [-0.5, 0, 0, 20], [0, 0.75, 0, -30], [0, 0, 0, 1]], dtype=float)
image = nib.Nifti2Image(ramp.astype("<i2"), sform)
image.header.set_xyzt_units("mm")
image.set_sform(sform, code=1)
image.set_qform(None, code=0)
nib.save(image, os.path.join(here, "ramp_sform_le.nii"))

# float32 stored as (value + 1024) / 2, big endian, scl_slope 2 and
# scl_inter -1024, a qform of 180 degrees about z with qfac -1 (every axis
# flipped), spacing 0.5, 0.75, 2 mm in metres (xyzt_units), origin
# (5, 6, 7) mm.
qform = np.array([[-0.5, 0, 0, 5], [0, -0.75, 0, 6], [0, 0, -2, 7], [0, 0, 0, 1]], dtype=float) / 1000
qform[3, 3] = 1
header = nib.Nifti2Header(endianness=">")
header.set_data_dtype(np.float32)
scaled = nib.Nifti2Image(((ramp + 1024) / 2).astype(">f4"), None, header=header)
scaled.set_qform(qform, code=1)
scaled.set_sform(None, code=0)
scaled.header.set_xyzt_units("meter")
scaled.header.set_slope_inter(2.0, -1024.0)
nib.save(scaled, os.path.join(here, "ramp_qform_be.nii"))
