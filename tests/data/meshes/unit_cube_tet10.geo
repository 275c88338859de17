// Unit cube in second-order tetrahedra (Gmsh element type 11): the fixture of
// the Tet10 node-order test in tests/unit/fem/SolidElementTest.cpp.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Mesh.MeshSizeMax = 0.5;
Mesh.ElementOrder = 2;
