// The slender solid bar of issue 18 (calculix_peer.py --model=bar): length L
// along x, square section a x a centred on the x axis, meshed with
// second-order elements: hex = 1, structured 20-node bricks (serendipity,
// Mesh.SecondOrderIncomplete), nx along and ns across each side; hex = 0,
// 10-node tetrahedra of size min(L/nx, a/ns). order = 3 or 4 (hex = 1):
// Lagrange bricks of that order (Hex64, Hex125) instead of Hex20. grade > 1:
// the elements along the bar grow geometrically from the root, each grade
// times the last (the clamped root's corner singularity wants small ones).
// Physical groups: the volume "blade", the faces "root" (x = 0) and "tip"
// (x = L).
//   gmsh -3 -setnumber nx 50 -setnumber ns 1 bar.geo -o bar.msh
//   gmsh -3 -setnumber nx 12 -setnumber ns 1 -setnumber order 4 -setnumber grade 1.2 bar.geo -o bar.msh
DefineConstant[
  L = {1.0, Name "Parameters/L"},
  a = {0.02, Name "Parameters/a"},
  nx = {50, Name "Parameters/nx"},
  ns = {1, Name "Parameters/ns"},
  hex = {1, Name "Parameters/hex"},
  order = {2, Name "Parameters/order"},
  grade = {1, Name "Parameters/grade"}
];
Point(1) = {0, -a/2, -a/2, L/nx};
Point(2) = {0,  a/2, -a/2, L/nx};
Point(3) = {0,  a/2,  a/2, L/nx};
Point(4) = {0, -a/2,  a/2, L/nx};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
If (hex)
  Transfinite Curve{1, 2, 3, 4} = ns + 1;
  Transfinite Surface{1};
  Recombine Surface{1};
  // Layer i ends at L (grade^i - 1) / (grade^nx - 1) of the way.
  ones[] = {};
  ends[] = {};
  For i In {1:nx}
    ones[] += 1;
    If (grade == 1)  // (Gmsh's ?: evaluates both branches: no 0 / 0 here)
      ends[] += i / nx;
    Else
      ends[] += (grade^i - 1) / (grade^nx - 1);
    EndIf
  EndFor
  out[] = Extrude {L, 0, 0} { Surface{1}; Layers{ones[], ends[]}; Recombine; };
Else
  Mesh.CharacteristicLengthMax = Min(L / nx, a / ns);
  out[] = Extrude {L, 0, 0} { Surface{1}; };
EndIf
Physical Volume("blade") = {out[1]};
Physical Surface("root") = {1};
Physical Surface("tip") = {out[0]};
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = (order == 2) ? 1 : 0;
Mesh.HighOrderOptimize = 0;
