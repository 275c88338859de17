// The bar of bar_hex.geo (length L along x, square section a x a centred on
// the x axis) meshed with unstructured 10-node tetrahedra, for the
// second-order solid element. h is the target element size:
// gmsh -3 -setnumber h 0.01 bar_tet10.geo
DefineConstant[
  L = {1.0, Name "Parameters/L"},
  a = {0.02, Name "Parameters/a"},
  h = {0.02, Name "Parameters/h"}
];

Point(1) = {0, -a/2, -a/2, h};
Point(2) = {0,  a/2, -a/2, h};
Point(3) = {0,  a/2,  a/2, h};
Point(4) = {0, -a/2,  a/2, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

out[] = Extrude {L, 0, 0} { Surface{1}; };
Physical Volume("blade") = {out[1]};
Physical Surface("root") = {1};
Physical Surface("tip") = {out[0]};

Mesh.CharacteristicLengthMax = h;
Mesh.ElementOrder = 2;
// Straight-sided quadratic elements: the geometry is all planes, and a
// high-order optimisation pass would only cost time.
Mesh.HighOrderOptimize = 0;
