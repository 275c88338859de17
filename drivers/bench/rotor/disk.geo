// A bladed disk's hub for the benchmark rotor's blades (bladed-disk.yaml):
// a steel prism with N flat sides (apothem a, axial length w along z) and a
// 12-sided bore of circumradius rb, clamped on the bore and spinning about
// z. Side k, physical surface "side<k>", has its outward normal at
// 360 k / N degrees about z; every side carries a blade. Meshed with
// 10-node tetrahedra of size h (Gmsh SDK, when the scene is read); the
// scene's "Mesh Parameters" (or bench_rotor --h=...) set h and N.
DefineConstant[
  N = {24, Name "Parameters/N"},
  a = {0.10, Name "Parameters/a"},
  w = {0.05, Name "Parameters/w"},
  rb = {0.03, Name "Parameters/rb"},
  h = {0.02, Name "Parameters/h"}
];
R = a / Cos(Pi / N);
For k In {0:N-1}
  Point(1 + k) = {R * Cos((2 * k - 1) * Pi / N), R * Sin((2 * k - 1) * Pi / N), 0, h};
EndFor
For k In {0:N-1}
  Line(1 + k) = {1 + k, 1 + (k + 1) % N};
EndFor
// The bore is a 12-sided polygon (arcs would leave their centre points in
// the mesh as unconnected nodes).
For k In {0:11}
  Point(N + 1 + k) = {rb * Cos(k * Pi / 6), rb * Sin(k * Pi / 6), 0, h};
EndFor
For k In {0:11}
  Line(N + 1 + k) = {N + 1 + k, N + 1 + (k + 1) % 12};
EndFor
Curve Loop(1) = {1:N};
Curve Loop(2) = {N+1:N+12};
Plane Surface(1) = {1, 2};
out[] = Extrude {0, 0, w} { Surface{1}; };
// out[]: top, volume, then one lateral surface per bounding curve in order
// (the N sides, then the twelve bore faces).
Physical Volume("hub") = {out[1]};
For k In {0:N-1}
  Physical Surface(Sprintf("side%g", k)) = {out[2 + k]};
EndFor
Physical Surface("bore") = {out[{N+2:N+13}]};
Mesh.CharacteristicLengthMax = h;
Mesh.ElementOrder = 2;
Mesh.HighOrderOptimize = 0;
