// MSH 4.1 files read without Gmsh (doc/architecture.md, "mesh"): the records
// MshStructureCheck kept while it checked the file, put into a Mesh as the
// Gmsh reader module (GmshReader.cpp) puts what Gmsh's SDK returns: nodes
// sorted by tag, physical groups by dimension and tag, each group's cells
// entity by entity (by tag) in file order, one block per element type.
// Loading the module costs ~0.18 s (libgmsh, OpenCASCADE and their ~80
// libraries; doc/benchmarks.md, "Elements of higher order against
// CalculiX") and ~40 MiB, more than reading a mesh of 1e4 cells; MSH 2.2
// files still go to Gmsh (CMS_MSH_READER=gmsh sends every file there).
#include "MshReader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "GmshTypes.hpp"
#include "cms/core/InputError.hpp"

namespace cms::mesh::detail {
namespace {

/// Gmsh's node order of its Lagrange hexahedra, as the lexicographic
/// position (i + (k+1) j + (k+1)^2 l, Mesh.hpp) of each of its nodes:
/// Gmsh 4.8's getElementProperties, the reference coordinates mapped to the
/// grid. The Gmsh reader module computes the same from Gmsh at run time;
/// MeshReader.NativeAndGmshReadersAgree compares the two on meshes of each.
constexpr int kHex27[27] = {0, 2, 8, 6, 18, 20, 26, 24, 1, 3, 9, 5, 11, 7, 17, 15, 19, 21, 23, 25, 4, 10, 12, 14, 16, 22, 13};
constexpr int kHex64[64] = {0,  3,  15, 12, 48, 51, 63, 60, 1,  2,  4,  8,  16, 32, 7,  11, 19, 35, 14, 13, 31, 47,
                            28, 44, 49, 50, 52, 56, 55, 59, 62, 61, 5,  9,  10, 6,  17, 18, 34, 33, 20, 36, 40, 24,
                            23, 27, 43, 39, 30, 29, 45, 46, 53, 54, 58, 57, 21, 22, 26, 25, 37, 38, 42, 41};
constexpr int kHex125[125] = {
    0,  4,  24,  20, 100, 104, 124, 120, 1,  2,   3,   5,   10,  15,  25,  50, 75,  9,  14, 19, 29, 54,  79,  23,  22,
    21, 49, 74,  99, 45,  70,  95,  101, 102, 103, 105, 110, 115, 109, 114, 119, 123, 122, 121, 6,  16,  18, 8,  11, 17,
    13, 7,  12,  26, 28,  78,  76,  27,  53,  77,  51,  52,  30,  80,  90,  40,  55,  85,  65, 35, 60,  34,  44,  94, 84,
    39, 69, 89,  59, 64,  48,  46,  96,  98,  47,  71,  97,  73,  72,  106, 108, 118, 116, 107, 113, 117, 111, 112, 31, 33,
    43, 41, 81,  83, 93,  91,  32,  36,  56,  38,  58,  42,  68,  66,  82,  86,  88,  92,  37,  57,  61,  63,  67, 87, 62};

const int* lexicographic(CellType type) {
  switch (type) {
    case CellType::Hex27: return kHex27;
    case CellType::Hex64: return kHex64;
    case CellType::Hex125: return kHex125;
    default: return nullptr;
  }
}

}  // namespace

Mesh meshFromMsh41(MshContent&& c, const std::string& source, void (*checkNodes)(const Mesh&)) {
  Mesh mesh;
  mesh.source = source;
  // Nodes, sorted by tag (the scan refused repeated tags and undefined ones).
  CMS_INPUT_CHECK(c.nodeTags.empty(), source << ": empty mesh (no nodes)");
  std::vector<std::size_t> order(c.nodeTags.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return c.nodeTags[a] < c.nodeTags[b]; });
  mesh.nodeTags.resize(order.size());
  mesh.coordinates.resize(3 * order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    mesh.nodeTags[i] = c.nodeTags[order[i]];
    for (int k = 0; k < 3; ++k) mesh.coordinates[3 * i + k] = c.coordinates[3 * order[i] + k];
  }
  for (std::size_t i = 0; i < mesh.nodeTags.size(); ++i)
    for (int k = 0; k < 3; ++k)
      CMS_INPUT_CHECK(!std::isfinite(mesh.coordinates[3 * i + k]),
                      source << ": node " << mesh.nodeTags[i] << " has a non-finite coordinate " << "xyz"[k]
                             << " = " << mesh.coordinates[3 * i + k]);
  if (checkNodes) checkNodes(mesh);
  // Every element's node is in $Nodes (the scan refused the others).
  const NodeIndex index(mesh.nodeTags);
  // Physical groups: (dim, tag) -> entities, both ascending, as Gmsh lists them.
  std::map<std::pair<int, long long>, std::vector<long long>> groups;
  for (const auto& [entity, tags] : c.physicals)
    for (long long tag : tags) {
      auto& entities = groups[{entity.first, tag}];
      if (entities.empty() || entities.back() != entity.second) entities.push_back(entity.second);
    }
  CMS_INPUT_CHECK(groups.empty(), source << ": no physical groups (name the parts and boundaries "
                                            "with Physical Volume/Surface/Curve/Point)");
  std::map<std::pair<int, long long>, std::vector<const MshContent::Block*>> blocksOf;
  for (const MshContent::Block& b : c.blocks) blocksOf[{b.dim, b.entity}].push_back(&b);
  std::map<std::pair<int, std::string>, long long> named;
  for (const auto& [key, entities] : groups) {
    const auto [dim, tag] = key;
    PhysicalGroup g;
    g.dim = dim;
    g.tag = static_cast<int>(tag);
    const auto name = c.names.find({dim, tag});
    g.name = name != c.names.end() ? name->second : "";
    if (g.name.empty()) g.name = std::to_string(dim) + ":" + std::to_string(tag);
    auto [it, fresh] = named.emplace(std::make_pair(dim, g.name), tag);
    CMS_INPUT_CHECK(!fresh, source << ": physical name \"" << g.name << "\" of dimension " << dim
                                   << " is used by two groups (tags " << it->second << " and " << tag << ")");
    std::map<int, std::size_t> blockOf;
    for (long long entity : entities) {
      const auto found = blocksOf.find({dim, entity});
      if (found == blocksOf.end()) continue;
      for (const MshContent::Block* src : found->second) {
        if (src->cellTags.empty()) continue;
        auto [b, added] = blockOf.emplace(src->type, g.blocks.size());
        if (added) {
          CellBlock block;
          block.gmshType = src->type;
          block.type = cellTypeOfGmsh(src->type);
          block.nodesPerCell = src->nodesPerCell;
          g.blocks.push_back(std::move(block));
        }
        CellBlock& block = g.blocks[b->second];
        const int* to = lexicographic(block.type);
        const std::size_t npc = static_cast<std::size_t>(block.nodesPerCell);
        for (std::size_t e = 0; e < src->cellTags.size(); ++e) {
          block.cellTags.push_back(src->cellTags[e]);
          const std::size_t first = block.nodes.size();
          block.nodes.resize(first + npc);
          for (std::size_t k = 0; k < npc; ++k) {
            block.nodes[first + (to ? static_cast<std::size_t>(to[k]) : k)] = index(src->nodes[e * npc + k]);
          }
        }
      }
    }
    CMS_INPUT_CHECK(g.blocks.empty(), source << ": physical group \"" << g.name << "\" (dimension " << dim
                                             << ", tag " << tag << ") has no cells");
    mesh.groups.push_back(std::move(g));
  }
  return mesh;
}

}  // namespace cms::mesh::detail
