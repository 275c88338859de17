// Hub of the benchmark rotor: a steel hexagonal prism (apothem a, axial
// length w along z) with a bore of circumradius rb, clamped on the bore and
// spinning about z. Three of its six flat sides carry blades: physical
// surfaces "side0", "side2", "side4" have outward normals at 0, 120 and 240
// degrees about z. Meshed with 10-node tetrahedra of size h (Gmsh SDK, when
// the scene is read); drivers/bench_rotor sets h through "Mesh Parameters".
DefineConstant[
  a = {0.10, Name "Parameters/a"},
  w = {0.05, Name "Parameters/w"},
  rb = {0.03, Name "Parameters/rb"},
  h = {0.02, Name "Parameters/h"}
];
R = a / Cos(Pi / 6);
For k In {0:5}
  Point(1 + k) = {R * Cos((2 * k - 1) * Pi / 6), R * Sin((2 * k - 1) * Pi / 6), 0, h};
EndFor
For k In {0:5}
  Line(1 + k) = {1 + k, 1 + (k + 1) % 6};
EndFor
// The bore is a 12-sided polygon (arcs would leave their centre points in
// the mesh as unconnected nodes).
For k In {0:11}
  Point(7 + k) = {rb * Cos(k * Pi / 6), rb * Sin(k * Pi / 6), 0, h};
EndFor
For k In {0:11}
  Line(7 + k) = {7 + k, 7 + (k + 1) % 12};
EndFor
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Curve Loop(2) = {7:18};
Plane Surface(1) = {1, 2};
out[] = Extrude {0, 0, w} { Surface{1}; };
// out[]: top, volume, then one lateral surface per bounding curve in order
// (the six sides, then the twelve bore faces).
Physical Volume("hub") = {out[1]};
Physical Surface("side0") = {out[2]};
Physical Surface("side2") = {out[4]};
Physical Surface("side4") = {out[6]};
Physical Surface("bore") = {out[{8:19}]};
Mesh.CharacteristicLengthMax = h;
Mesh.ElementOrder = 2;
Mesh.HighOrderOptimize = 0;
