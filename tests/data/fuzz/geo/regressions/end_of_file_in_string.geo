// A beam axis along x from 0 to L with n two-node line elements, for frame
// (beam) elements: gmsh -1 -setnumber n 40 beam_line.geo
DefineConstant[
  L = {1.0, Name "Paramete