// Gmsh's element type numbers as cms's cell types, shared by the reader that
// uses Gmsh's SDK (GmshReader.cpp, the module) and the one that does not
// (MshReader.cpp). Headers only: the module links nothing of cms's.
#pragma once

#include "cms/mesh/Mesh.hpp"

namespace cms::mesh::detail {

inline CellType cellTypeOfGmsh(int gmshType) {
  switch (gmshType) {
    case 15: return CellType::Point1;
    case 1: return CellType::Line2;
    case 8: return CellType::Line3;
    case 2: return CellType::Tri3;
    case 9: return CellType::Tri6;
    case 3: return CellType::Quad4;
    case 4: return CellType::Tet4;
    case 11: return CellType::Tet10;
    case 5: return CellType::Hex8;
    case 17: return CellType::Hex20;
    case 18: return CellType::Wedge15;
    case 12: return CellType::Hex27;
    case 92: return CellType::Hex64;
    case 93: return CellType::Hex125;
    default: return CellType::Other;
  }
}

}  // namespace cms::mesh::detail
