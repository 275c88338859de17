// What the reader that uses Gmsh's SDK (GmshReader.cpp, the module) and the
// one that does not (MshReader.cpp) share: Gmsh's element type numbers as
// cms's cell types, and node tags to indices. Headers only: the module links
// nothing of cms's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cms/core/InputError.hpp"
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

/// A Lagrange hexahedron of order k (Hex27, Hex64, Hex125) as Gmsh's SDK
/// describes its type (getElementProperties: name, dimension, order, node
/// count, reference coordinates on [-1, 1]^3): lexicographic[g] is the
/// position in cms's order (Mesh.hpp) of Gmsh's node g. Throws InputError
/// naming the type when the description is not the (k+1)^3-node brick with
/// its nodes on the equispaced grid, each once: a Gmsh whose numbering
/// differs is refused rather than read into scrambled elements.
inline std::vector<int> lexicographicFromReference(int gmshType, CellType type, const std::string& name, int dim,
                                                   int order, int count, const std::vector<double>& reference) {
  const int k = lagrangeHexOrder(type);
  const int m = k + 1;
  if (k == 0 || dim != 3 || order != k || count != m * m * m || reference.size() != 3u * static_cast<std::size_t>(count))
    throw InputError("Gmsh reports element type " + std::to_string(gmshType) + " as \"" + name + "\" of order " +
                     std::to_string(order) + " with " + std::to_string(count) + " nodes; cms expects the " +
                     std::to_string(m * m * m) + "-node Lagrange hexahedron");
  std::vector<int> to(count), seen(count, 0);
  for (int g = 0; g < count; ++g) {
    int ijk[3];
    for (int d = 0; d < 3; ++d) {
      const double t = 0.5 * (reference[3 * g + d] + 1.0) * k;  // 0..k
      ijk[d] = static_cast<int>(std::lround(t));
      if (!(std::abs(t - ijk[d]) <= 1e-6) || ijk[d] < 0 || ijk[d] > k)
        throw InputError("Gmsh's reference node " + std::to_string(g) + " of element type " +
                         std::to_string(gmshType) + " is not on the equispaced grid of order " + std::to_string(k));
    }
    to[g] = ijk[0] + m * (ijk[1] + m * ijk[2]);
    if (seen[to[g]]++)
      throw InputError("Gmsh's reference nodes of element type " + std::to_string(gmshType) + " repeat a grid point");
  }
  return to;
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
