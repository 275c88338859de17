// What the reader that uses Gmsh's SDK (GmshReader.cpp, the module) and the
// one that does not (MshReader.cpp) share: Gmsh's element type numbers as
// cms's cell types, and node tags to indices. Headers only: the module links
// nothing of cms's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

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

/// Node tag -> index: a table when tags are dense enough, else a search.
class NodeIndex {
public:
  explicit NodeIndex(const std::vector<std::size_t>& sortedTags) : tags_(sortedTags) {
    if (!tags_.empty() && tags_.back() <= 4 * tags_.size() + 1024) {
      table_.assign(tags_.back() + 1, -1);
      for (std::size_t i = 0; i < tags_.size(); ++i) table_[tags_[i]] = static_cast<std::int64_t>(i);
    }
  }
  std::int64_t operator()(std::size_t tag) const {
    if (!table_.empty()) return tag < table_.size() ? table_[tag] : -1;
    auto it = std::lower_bound(tags_.begin(), tags_.end(), tag);
    return it != tags_.end() && *it == tag ? static_cast<std::int64_t>(it - tags_.begin()) : -1;
  }

private:
  const std::vector<std::size_t>& tags_;
  std::vector<std::int64_t> table_;
};

}  // namespace cms::mesh::detail
