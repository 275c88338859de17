// A coarse square in triangles, its edge and corner named: a .geo seed for
// the fuzz driver (tests/unit/scene/FuzzDriver.cpp).
h = 0.5;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 1000000, h};
Point(4) = {0, 1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("plate") = {1};
Physical Curve("edge") = {4};
Physical Point("corner") = {1};
