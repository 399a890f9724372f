#!/usr/bin/python3
"""Writes two_volumes_v22.msh (Gmsh) again as VTK files, with VTK's own
writers in each of their layouts, for the reader tests:
  two_volumes_default.vtu      XML, appended, base64, zlib (VTK's defaults)
  two_volumes_raw.vtu          XML, appended, raw, zlib (ParaView's default)
  two_volumes_raw_plain.vtu    XML, appended, raw, uncompressed
  two_volumes_b64_plain64.vtu  XML, appended, base64, uncompressed, 64-bit headers
  two_volumes_inline.vtu       XML, inline base64, zlib
  two_volumes_legacy51.vtk     legacy 5.1 (VTK 9's default), binary
  two_volumes_legacy42.vtk     legacy 4.2, ASCII
  two_volumes_o2.vtu           two_volumes_o2_v22.msh (the same mesh of
                               second order: 10-node tetrahedra) as XML,
                               VTK's defaults
  two_volumes_o2_legacy51.vtk  the same as legacy 5.1, binary
The triangles of the Gmsh file are kept too (readers skip them); the cell
array gmsh:physical holds the physical tags. The Gmsh files come from
two_volumes.geo: gmsh -3 [-order 2] two_volumes.geo -format msh22|msh40|msh41.
Needs python3-vtk9:
  /usr/bin/python3 tests/plugins/tetra_brain/data/write_vtk.py
"""
import os

import vtk

HERE = os.path.dirname(os.path.abspath(__file__))
# Gmsh element type -> VTK cell type and the Gmsh node order in VTK's
# (second-order tetrahedra list their last two edge midpoints the other way).
GMSH_TO_VTK = {2: (vtk.VTK_TRIANGLE, [0, 1, 2]), 4: (vtk.VTK_TETRA, [0, 1, 2, 3]),
               9: (vtk.VTK_QUADRATIC_TRIANGLE, [0, 1, 2, 3, 4, 5]),
               11: (vtk.VTK_QUADRATIC_TETRA, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8])}


def read_gmsh22(path):
    """The points, and the cells as (VTK type, point indices, physical tag), of a Gmsh 2.2 ASCII file."""
    lines = open(path).read().split('\n')
    start = lines.index('$Nodes')
    points, index_of = [], {}
    for line in lines[start + 2:start + 2 + int(lines[start + 1])]:
        tag, x, y, z = line.split()
        index_of[int(tag)] = len(points)
        points.append((float(x), float(y), float(z)))
    start = lines.index('$Elements')
    cells = []
    for line in lines[start + 2:start + 2 + int(lines[start + 1])]:
        values = [int(v) for v in line.split()]
        element_type, tag_count = values[1], values[2]
        nodes = [index_of[n] for n in values[3 + tag_count:]]
        if element_type in GMSH_TO_VTK:
            cell_type, order = GMSH_TO_VTK[element_type]
            cells.append((cell_type, [nodes[k] for k in order], values[3]))
    return points, cells


def grid_of(points, cells):
    vtk_points = vtk.vtkPoints()
    vtk_points.SetDataTypeToDouble()
    for p in points:
        vtk_points.InsertNextPoint(*p)
    grid = vtk.vtkUnstructuredGrid()
    grid.SetPoints(vtk_points)
    labels = vtk.vtkIntArray()
    labels.SetName('gmsh:physical')
    for cell_type, nodes, label in cells:
        grid.InsertNextCell(cell_type, len(nodes), nodes)
        labels.InsertNextValue(label)
    grid.GetCellData().AddArray(labels)
    return grid


def write(grid, name, appended=True, encoded=True, compressed=True, header64=False):
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetFileName(os.path.join(HERE, 'two_volumes_' + name + '.vtu'))
    writer.SetInputData(grid)
    if appended:
        writer.SetDataModeToAppended()
    else:
        writer.SetDataModeToBinary()
    writer.SetEncodeAppendedData(encoded)
    if not compressed:
        writer.SetCompressorTypeToNone()
    if header64:
        writer.SetHeaderTypeToUInt64()
    writer.Write()


def write_legacy(grid, name, binary, version=None):
    writer = vtk.vtkUnstructuredGridWriter()
    writer.SetFileName(os.path.join(HERE, 'two_volumes_' + name + '.vtk'))
    writer.SetInputData(grid)
    if binary:
        writer.SetFileTypeToBinary()
    if version:
        writer.SetFileVersion(version)
    writer.Write()


def main():
    grid = grid_of(*read_gmsh22(os.path.join(HERE, 'two_volumes_v22.msh')))
    write(grid, 'default', appended=True, encoded=True, compressed=True)
    write(grid, 'raw', appended=True, encoded=False, compressed=True)
    write(grid, 'raw_plain', appended=True, encoded=False, compressed=False)
    write(grid, 'b64_plain64', appended=True, encoded=True, compressed=False, header64=True)
    write(grid, 'inline', appended=False, encoded=True, compressed=True)
    write_legacy(grid, 'legacy51', binary=True)
    write_legacy(grid, 'legacy42', binary=False, version=42)
    second_order = grid_of(*read_gmsh22(os.path.join(HERE, 'two_volumes_o2_v22.msh')))
    write(second_order, 'o2')
    write_legacy(second_order, 'o2_legacy51', binary=True)


if __name__ == '__main__':
    main()
