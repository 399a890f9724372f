// Two boxes sharing a face, meshed conformally, each its own physical volume.
// Regenerate: gmsh -3 two_volumes.geo -format msh41 -o two_volumes_v41.msh
// (msh40, msh22 for the other versions).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 2, 2};
Box(2) = {2, 0, 0, 2, 2, 2};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("grey", 5) = {1};
Physical Volume("white", 6) = {2};
Physical Surface("outer", 3) = {1};
Mesh.MeshSizeMax = 1.2;
Mesh.MeshSizeMin = 1.2;
