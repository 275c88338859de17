// Blade of the benchmark rotor: a straight steel plate along x (length L,
// chord c along z, thickness t along y), root face "root" at x = 0 centred
// on the x axis; the scene places three copies on the hub's sides.
// 10-node tetrahedra of size h; drivers/bench_rotor sets h through
// "Mesh Parameters".
DefineConstant[
  L = {0.8, Name "Parameters/L"},
  c = {0.04, Name "Parameters/c"},
  t = {0.016, Name "Parameters/t"},
  h = {0.02, Name "Parameters/h"}
];
Point(1) = {0, -t/2, -c/2, h};
Point(2) = {0,  t/2, -c/2, h};
Point(3) = {0,  t/2,  c/2, h};
Point(4) = {0, -t/2,  c/2, h};
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
