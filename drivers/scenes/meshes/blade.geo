// A slender rectangular blade along x (length L, chord c along y, thickness t
// along z, centred on the x axis), meshed with unstructured 10-node
// tetrahedra, for the solid-versus-beam rotating-blade validation. Chord > t
// keeps flapwise (z) and lead-lag (y) modes apart.
// Meshed when the scene is read (Gmsh SDK): gmsh -3 blade.geo to look at it.
DefineConstant[
  L = {1.0, Name "Parameters/L"},
  c = {0.04, Name "Parameters/c"},
  t = {0.02, Name "Parameters/t"},
  h = {0.025, Name "Parameters/h"}
];

Point(1) = {0, -c/2, -t/2, h};
Point(2) = {0,  c/2, -t/2, h};
Point(3) = {0,  c/2,  t/2, h};
Point(4) = {0, -c/2,  t/2, h};
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
Mesh.HighOrderOptimize = 0;
