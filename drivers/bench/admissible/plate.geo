// A thin rectangular plate for the admissible-vector benchmark (issue 14
// item 3): span L along x, chord c along y (centred on the x axis),
// thickness t along z (centred on z = 0). The mid-plane rectangle is a
// structured nx x ny grid of triangles, extruded through the thickness in nz
// layers of tetrahedra (no Recombine: each prism split into three tets), all
// of second order (Tet10), so the mesh is regular and does not depend on
// Gmsh's 3D mesher. "root" is the edge face at x = 0 (clamped through the
// attachment), "tip" the face at x = L.
//   gmsh -3 plate.geo     (to look at it)
DefineConstant[
  L = {0.5, Name "Parameters/L"},
  c = {0.3, Name "Parameters/c"},
  t = {0.005, Name "Parameters/t"},
  nx = {24, Name "Parameters/nx"},
  ny = {14, Name "Parameters/ny"},
  nz = {1, Name "Parameters/nz"}
];

Point(1) = {0, -c/2, -t/2};
Point(2) = {L, -c/2, -t/2};
Point(3) = {L,  c/2, -t/2};
Point(4) = {0,  c/2, -t/2};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1};

out[] = Extrude {0, 0, t} { Surface{1}; Layers{nz}; };
// out[0]: the top face, out[1]: the volume, out[2..5]: the faces swept by
// lines 1..4 (line 4 lies at x = 0, line 2 at x = L).
Physical Volume("plate") = {out[1]};
Physical Surface("root") = {out[5]};
Physical Surface("tip") = {out[3]};

Mesh.ElementOrder = 2;
Mesh.HighOrderOptimize = 0;
