// A straight bar along x: length L, square section a x a centred on the x
// axis, meshed with structured 8-node hexahedra (a transfinite, recombined
// root face extruded in layers). Element counts are parameters so a test or
// a convergence study can refine it: gmsh -3 -setnumber nx 40 bar_hex.geo
DefineConstant[
  L = {1.0, Name "Parameters/L"},
  a = {0.02, Name "Parameters/a"},
  nx = {20, Name "Parameters/nx"},   // elements along the bar
  ns = {2, Name "Parameters/ns"}     // elements across each side of the section
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
// out[0] is the face at x = L, out[1] the volume.
Physical Volume("blade") = {out[1]};
Physical Surface("root") = {1};
Physical Surface("tip") = {out[0]};
