// A script Gmsh's parser takes minutes over (two billion loop steps) before
// its one point: a test's stand-in for a large mesh still being made when
// the scene that asked for it is refused (test_scene, "ARefusedScene...").
For i In {1:2000000000}
  x = i;
EndFor
Point(1) = {0, 0, 0};
