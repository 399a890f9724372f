#!/usr/bin/env python3
"""Writes a DICOM MR series as some scanners do, with pydicom (an independent
writer): 6 slices of 8 x 5 pixels on an oblique-free axial plane, slice
positions rounded unevenly (steps 7.07, 6.97, 7.12, 6.90, 7.05 mm), and the
third file padded with 64 KiB of zeros after its data set.

    write_scanner_dicom.py OUT_DIR

The stored value of pixel (column c, row r) of slice k is 100 c + 10 r + k,
RescaleSlope 1 and RescaleIntercept 0; PixelSpacing 0.9 (rows) x 0.8
(columns) mm; ImagePositionPatient (-5, 12, z_k).
"""
import os
import sys

import pydicom
from pydicom.dataset import Dataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, MRImageStorage, generate_uid

POSITIONS = [0.0, 7.07, 14.04, 21.16, 28.06, 35.11]
COLUMNS, ROWS = 8, 5


def write_slice(path, k, z, series_uid, study_uid, frame_uid):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = MRImageStorage
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = Dataset()
    ds.file_meta = meta
    ds.is_little_endian = True
    ds.is_implicit_VR = False
    ds.SOPClassUID = MRImageStorage
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.Modality = "MR"
    ds.SeriesInstanceUID = series_uid
    ds.StudyInstanceUID = study_uid
    ds.FrameOfReferenceUID = frame_uid
    ds.SeriesDescription = "uneven oblique-free MR"
    ds.InstanceNumber = k + 1
    ds.ImagePositionPatient = [-5.0, 12.0, z]
    ds.ImageOrientationPatient = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    ds.PixelSpacing = [0.9, 0.8]
    ds.SliceThickness = 7.0
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.Rows = ROWS
    ds.Columns = COLUMNS
    ds.BitsAllocated = 16
    ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 1
    ds.RescaleSlope = 1
    ds.RescaleIntercept = 0
    values = [100 * c + 10 * r + k for r in range(ROWS) for c in range(COLUMNS)]
    ds.PixelData = b"".join(v.to_bytes(2, "little", signed=True) for v in values)
    pydicom.dcmwrite(path, ds, write_like_original=False)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    series_uid, study_uid, frame_uid = generate_uid(), generate_uid(), generate_uid()
    for k, z in enumerate(POSITIONS):
        path = os.path.join(out, "IM%04d" % (len(POSITIONS) - k))  # named against their order
        write_slice(path, k, z, series_uid, study_uid, frame_uid)
        if k == 2:
            with open(path, "ab") as f:
                f.write(b"\0" * 65536)


if __name__ == "__main__":
    main()
