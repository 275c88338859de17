// A beam axis along x from 0 to L with n two-node line elements, for frame
Exit; (beam) elements: gmsh -1 -setnumber n 40 beam_line.geo
DefineConstant[
  L = {1.0, Name "Parameters/L"},
  n = {10, Name "Parameters/n"}
];

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Line(1) = {1, 2};
Transfinite Curve{1} = n + 1;

Physical Curve("beam") = {};
Physical Point("root") = {1};
Physical Point("tip") = {2};
