#!/usr/bin/env python3
"""Writes one small head three ways, each by its own format's rules and not
by the project's writers: a DICOM series with pydicom (LPS positions), a
NIfTI-1 file packed from nifti1.h's layout (its sform in RAS, as nibabel and
3D Slicer write it), and an NRRD whose space is right-anterior-superior.

    write_head_both_ways.py OUT_DIR

The head is 24 x 20 x 16 voxels of 1.0 x 1.25 x 2.0 mm, its first voxel at
LPS (-11.5, -9.0, 40.0) mm. Soft tissue (100) everywhere, and a dense lump
(1000) only on the patient's left, to the front and high up: voxels with
i >= 16, j < 6 and k >= 10 (LPS +x is the left, -y the front). A reader that
mirrors a frame puts the lump on the right, or at the back.
"""
import os
import struct
import sys

NX, NY, NZ = 24, 20, 16
SPACING = (1.0, 1.25, 2.0)
ORIGIN_LPS = (-11.5, -9.0, 40.0)


def value(i, j, k):
    return 1000 if (i >= 16 and j < 6 and k >= 10) else 100


def write_dicom(out):
    import pydicom
    from pydicom.dataset import Dataset, FileMetaDataset
    from pydicom.uid import CTImageStorage, ExplicitVRLittleEndian, generate_uid

    os.makedirs(out, exist_ok=True)
    series, study, frame = generate_uid(), generate_uid(), generate_uid()
    for k in range(NZ):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = CTImageStorage
        meta.MediaStorageSOPInstanceUID = generate_uid()
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        ds = Dataset()
        ds.file_meta = meta
        ds.is_little_endian = True
        ds.is_implicit_VR = False
        ds.SOPClassUID = CTImageStorage
        ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
        ds.Modality = "CT"
        ds.SeriesInstanceUID, ds.StudyInstanceUID, ds.FrameOfReferenceUID = series, study, frame
        ds.InstanceNumber = k + 1
        ds.ImagePositionPatient = [ORIGIN_LPS[0], ORIGIN_LPS[1], ORIGIN_LPS[2] + k * SPACING[2]]
        ds.ImageOrientationPatient = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]  # rows along +x (L), columns along +y (P)
        ds.PixelSpacing = [SPACING[1], SPACING[0]]  # between rows, then between columns
        ds.SliceThickness = SPACING[2]
        ds.SamplesPerPixel = 1
        ds.PhotometricInterpretation = "MONOCHROME2"
        ds.Rows, ds.Columns = NY, NX
        ds.BitsAllocated = ds.BitsStored = 16
        ds.HighBit = 15
        ds.PixelRepresentation = 1
        ds.RescaleSlope, ds.RescaleIntercept = 1, 0
        pixels = [value(i, j, k) for j in range(NY) for i in range(NX)]
        ds.PixelData = b"".join(v.to_bytes(2, "little", signed=True) for v in pixels)
        pydicom.dcmwrite(os.path.join(out, "CT%03d.dcm" % k), ds, write_like_original=False)


def samples():
    return b"".join(struct.pack("<h", value(i, j, k)) for k in range(NZ) for j in range(NY) for i in range(NX))


def write_nifti(path):
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, NX, NY, NZ, 1, 1, 1, 1)
    struct.pack_into("<h", h, 70, 4)  # DT_INT16
    struct.pack_into("<h", h, 72, 16)
    struct.pack_into("<8f", h, 76, 1.0, *SPACING, 1, 1, 1, 1)
    struct.pack_into("<f", h, 108, 352.0)
    struct.pack_into("<f", h, 112, 1.0)
    h[123] = 2  # NIFTI_UNITS_MM
    struct.pack_into("<h", h, 252, 0)  # no qform
    struct.pack_into("<h", h, 254, 1)  # sform: scanner anatomical, RAS
    # RAS = (-x, -y, z) of LPS: the sform's rows for x and y negated.
    struct.pack_into("<4f", h, 280, -SPACING[0], 0, 0, -ORIGIN_LPS[0])
    struct.pack_into("<4f", h, 296, 0, -SPACING[1], 0, -ORIGIN_LPS[1])
    struct.pack_into("<4f", h, 312, 0, 0, SPACING[2], ORIGIN_LPS[2])
    h[344:348] = b"n+1\0"
    with open(path, "wb") as f:
        f.write(bytes(h) + samples())


def write_nrrd(path):
    origin_ras = (-ORIGIN_LPS[0], -ORIGIN_LPS[1], ORIGIN_LPS[2])
    header = (
        "NRRD0004\n"
        "type: int16\n"
        "dimension: 3\n"
        "space: right-anterior-superior\n"
        "sizes: %d %d %d\n"
        "space directions: (%g,0,0) (0,%g,0) (0,0,%g)\n"
        "endian: little\n"
        "encoding: raw\n"
        "space origin: (%g,%g,%g)\n\n"
        % (NX, NY, NZ, -SPACING[0], -SPACING[1], SPACING[2], *origin_ras)
    )
    with open(path, "wb") as f:
        f.write(header.encode() + samples())


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    write_dicom(os.path.join(out, "dicom"))
    write_nifti(os.path.join(out, "head.nii"))
    write_nrrd(os.path.join(out, "head.nrrd"))


if __name__ == "__main__":
    main()
