// The benchmark hub of hub.geo with all six sides named, for the six-blade
// rotor (rotor6.yaml): the same geometry and mesh, three more node sets.
Include "hub.geo";
Physical Surface("side1") = {out[3]};
Physical Surface("side3") = {out[5]};
Physical Surface("side5") = {out[7]};
