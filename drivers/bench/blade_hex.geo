// Benchmark blade: a bar along x (length L, square section a x a centred on
// the x axis), structured 8-node hexahedra, nx along and ns across each side.
// bench_assembly sets nx, ns and a (a = ns L / nx keeps the elements cubic).
DefineConstant[
  L = {1.0, Name "Parameters/L"},
  a = {0.02, Name "Parameters/a"},
  nx = {50, Name "Parameters/nx"},
  ns = {10, Name "Parameters/ns"}
];
Point(1) = {0, -a/2, -a/2};
Point(2) = {0,  a/2, -a/2};
Point(3) = {0,  a/2,  a/2};
Point(4) = {0, -a/2,  a/2};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = ns + 1;
Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {L, 0, 0} { Surface{1}; Layers{nx}; Recombine; };
Physical Volume("blade") = {out[1]};
Physical Surface("root") = {1};
Physical Surface("tip") = {out[0]};
