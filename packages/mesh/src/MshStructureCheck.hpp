// Structural check of a .msh file before Gmsh's SDK reads it (Gmsh 4.8
// trusts the file: see MshStructureCheck.cpp for what it does on corrupted
// input). Private to the mesh package.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace cms::mesh::detail {

/// What a scan of an MSH 4.1 file keeps for the reader that does without
/// Gmsh (MshReader.cpp): the file's records as they are, in file order.
struct MshContent {
  bool captured = false;  ///< false: not MSH 4.1 (MSH 2.2 is read by Gmsh)
  std::map<std::pair<long long, long long>, std::string> names;         ///< (dim, physical tag) -> name
  std::map<std::pair<int, long long>, std::vector<long long>> physicals;  ///< (dim, entity) -> physical tags
  std::vector<std::uint64_t> nodeTags;
  std::vector<double> coordinates;  ///< x, y, z of nodeTags[i] at 3i..3i+2
  struct Block {
    int dim = 0;
    long long entity = 0;
    int type = 0, nodesPerCell = 0;
    std::vector<std::uint64_t> cellTags, nodes;  ///< nodes: nodesPerCell node tags per cell
  };
  std::vector<Block> blocks;
};

/// Walks the bytes of a .msh file (format 2.2 or 4.1, ASCII or binary) once,
/// allocating nothing from its counts; throws cms::InputError naming the file
/// and the line (or section and byte offset) of the first defect. With
/// `content`, an MSH 4.1 file's records are kept there as they are read.
void checkMshStructure(const std::string& path, const std::string& bytes, MshContent* content = nullptr);

}  // namespace cms::mesh::detail
