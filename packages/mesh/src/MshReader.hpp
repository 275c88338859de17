// MSH 4.1 read without Gmsh (MshReader.cpp). Private to the mesh package.
#pragma once

#include <string>

#include "MshStructureCheck.hpp"
#include "cms/mesh/Mesh.hpp"

namespace cms::mesh::detail {

/// The mesh of a scanned MSH 4.1 file (c.captured), messages naming
/// `source`; checkNodes runs between the nodes and the cells, as in the
/// Gmsh reader module. Throws cms::InputError.
Mesh meshFromMsh41(MshContent&& c, const std::string& source, void (*checkNodes)(const Mesh&));

}  // namespace cms::mesh::detail
