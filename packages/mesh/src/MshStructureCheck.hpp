// Structural check of a .msh file before Gmsh's SDK reads it (Gmsh 4.8
// trusts the file: see MshStructureCheck.cpp for what it does on corrupted
// input). Private to the mesh package.
#pragma once

#include <string>

namespace cms::mesh::detail {

/// Walks the bytes of a .msh file (format 2.2 or 4.1, ASCII or binary) once,
/// allocating nothing from its counts; throws cms::InputError naming the file
/// and the line (or section and byte offset) of the first defect.
void checkMshStructure(const std::string& path, const std::string& bytes);

}  // namespace cms::mesh::detail
