// The Gmsh reader module (doc/architecture.md, "mesh"): the one place the
// running program touches Gmsh's SDK. Built as a module of its own and
// loaded by Mesh.cpp (dlopen) on the first .msh or .geo read, so that a run
// without a Gmsh mesh (an .inp deck, beams and point masses, Matrix Market
// substructures) never maps libgmsh and OpenCASCADE: ~40 MiB of resident
// pages and 82 of the program's 138 shared libraries (doc/benchmarks.md,
// "The bar's memory"). It links Gmsh and nothing of cms's but headers.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <new>
#include <string>
#include <vector>

#include <gmsh.h>

#include "cms/core/InputError.hpp"
#include "cms/mesh/Mesh.hpp"
#include "GmshReader.hpp"
#include "GmshSession.hpp"
#include "GmshTypes.hpp"

namespace cms::mesh {
namespace {

using detail::GmshSession;
using detail::firstError;

using detail::cellTypeOfGmsh;
using detail::NodeIndex;

/// For a Lagrange hexahedron (Hex27, Hex64, Hex125): lexicographic[g] is
/// the position in cms's order (Mesh.hpp) of Gmsh's node g, from Gmsh's own
/// reference coordinates of its nodes (detail::lexicographicFromReference).
/// Empty for every other type: those keep Gmsh's order.
std::vector<int> lexicographicOrder(int gmshType, CellType type) {
  if (lagrangeHexOrder(type) == 0) return {};
  std::string name;
  int dim = 0, order = 0, count = 0, primary = 0;
  std::vector<double> reference;
  gmsh::model::mesh::getElementProperties(gmshType, name, dim, order, count, reference, primary);
  return detail::lexicographicFromReference(gmshType, type, name, dim, order, count, reference);
}

void readNodes(Mesh& mesh) {
  std::vector<std::size_t> tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(tags, coord, parametric, -1, -1, false, false);
  CMS_INPUT_CHECK(tags.empty(), mesh.source << ": empty mesh (no nodes)");
  CMS_INPUT_CHECK(coord.size() != 3 * tags.size(),
                  mesh.source << ": Gmsh returned " << coord.size() << " coordinates for " << tags.size()
                              << " nodes");
  std::vector<std::size_t> order(tags.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tags[a] < tags[b]; });
  mesh.nodeTags.resize(tags.size());
  mesh.coordinates.resize(coord.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    mesh.nodeTags[i] = tags[order[i]];
    for (int c = 0; c < 3; ++c) mesh.coordinates[3 * i + c] = coord[3 * order[i] + c];
    if (i > 0)
      CMS_INPUT_CHECK(mesh.nodeTags[i] == mesh.nodeTags[i - 1],
                      mesh.source << ": node tag " << mesh.nodeTags[i] << " is used by two nodes");
  }
  for (std::size_t i = 0; i < mesh.nodeTags.size(); ++i)
    for (int c = 0; c < 3; ++c)
      CMS_INPUT_CHECK(!std::isfinite(mesh.coordinates[3 * i + c]),
                      mesh.source << ": node " << mesh.nodeTags[i] << " has a non-finite coordinate "
                                  << "xyz"[c] << " = " << mesh.coordinates[3 * i + c]);
}

void readGroups(Mesh& mesh) {
  gmsh::vectorpair dimTags;
  gmsh::model::getPhysicalGroups(dimTags);
  CMS_INPUT_CHECK(dimTags.empty(), mesh.source << ": no physical groups (name the parts and boundaries "
                                                  "with Physical Volume/Surface/Curve/Point)");
  const NodeIndex index(mesh.nodeTags);
  std::map<std::pair<int, std::string>, int> named;
  for (const auto& [dim, tag] : dimTags) {
    PhysicalGroup g;
    g.dim = dim;
    g.tag = tag;
    gmsh::model::getPhysicalName(dim, tag, g.name);
    if (g.name.empty()) g.name = std::to_string(dim) + ":" + std::to_string(tag);
    auto [it, fresh] = named.emplace(std::make_pair(dim, g.name), tag);
    CMS_INPUT_CHECK(!fresh, mesh.source << ": physical name \"" << g.name << "\" of dimension " << dim
                                        << " is used by two groups (tags " << it->second << " and " << tag
                                        << ")");
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    std::map<int, std::size_t> blockOf;
    for (int entity : entities) {
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> elementTags, nodeTags;
      gmsh::model::mesh::getElements(types, elementTags, nodeTags, dim, entity);
      for (std::size_t t = 0; t < types.size(); ++t) {
        if (elementTags[t].empty()) continue;
        auto [b, added] = blockOf.emplace(types[t], g.blocks.size());
        if (added) {
          CellBlock block;
          block.gmshType = types[t];
          block.type = cellTypeOfGmsh(types[t]);
          block.nodesPerCell = static_cast<int>(nodeTags[t].size() / elementTags[t].size());
          g.blocks.push_back(std::move(block));
        }
        CellBlock& block = g.blocks[b->second];
        const std::vector<int> to = lexicographicOrder(types[t], block.type);
        const std::size_t npc = static_cast<std::size_t>(block.nodesPerCell);
        CMS_INPUT_CHECK(npc == 0 || nodeTags[t].size() != npc * elementTags[t].size(),
                        mesh.source << ": element block of type " << types[t] << " in physical group \""
                                    << g.name << "\" has inconsistent node counts");
        CMS_INPUT_CHECK(!to.empty() && to.size() != npc,
                        mesh.source << ": element block of type " << types[t] << " in physical group \""
                                    << g.name << "\" has " << npc << " nodes per cell, not " << to.size());
        for (std::size_t e = 0; e < elementTags[t].size(); ++e) {
          block.cellTags.push_back(elementTags[t][e]);
          const std::size_t first = block.nodes.size();
          block.nodes.resize(first + npc);
          for (std::size_t k = 0; k < npc; ++k) {
            const std::size_t nodeTag = nodeTags[t][e * npc + k];
            const std::int64_t i = index(nodeTag);
            CMS_INPUT_CHECK(i < 0, mesh.source << ": element " << elementTags[t][e] << " refers to node "
                                               << nodeTag << ", which is not in the mesh");
            block.nodes[first + (to.empty() ? k : static_cast<std::size_t>(to[k]))] = i;
          }
        }
      }
    }
    CMS_INPUT_CHECK(g.blocks.empty(), mesh.source << ": physical group \"" << g.name << "\" (dimension "
                                                  << dim << ", tag " << tag << ") has no cells");
    mesh.groups.push_back(std::move(g));
  }
}

/// Reads a .msh through Gmsh (the file passed checkMshStructure). Gmsh's own
/// errors while the session is open become InputErrors naming `source`;
/// the rest (initialize, finalize) are turned into one at the entry point.
Mesh readMsh(const std::string& path, const std::string& source, detail::GmshNodeCheck checkNodes) {
  GmshSession session;
  try {
    gmsh::open(path);
    Mesh mesh;
    mesh.source = source;
    readNodes(mesh);
    checkNodes(mesh);
    readGroups(mesh);
    return mesh;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::string& message) {  // how Gmsh 4.8 raises its errors
    const std::string first = firstError();
    throw InputError(source + ": " + (first.empty() ? message : first));
  } catch (...) {
    // Read Gmsh's message while the session that raised it is still open.
    std::string message = firstError();
    try {
      if (message.empty()) gmsh::logger::getLastError(message);
    } catch (...) {
    }
    if (!message.empty()) throw InputError(source + ": " + message);
    throw;
  }
}

}  // namespace
}  // namespace cms::mesh

// The module's one entry point (GmshReader.hpp): no exception crosses it.
extern "C" int cms_gmsh_read_msh(const char* path, const char* source, cms::mesh::Mesh* mesh, std::string* message,
                                 cms::mesh::detail::GmshNodeCheck checkNodes) {
  using namespace cms::mesh::detail;
  try {
    *mesh = cms::mesh::readMsh(path, source, checkNodes);
    return kGmshReadOk;
  } catch (const cms::InputError& e) {
    *message = e.what();
  } catch (const std::bad_alloc&) {
    // Past the scan no count in the file drives an allocation: running out
    // of memory is the machine's limit, not malformed input.
    return kGmshReadOutOfMemory;
  } catch (const std::string& m) {  // from initialize / finalize
    *message = std::string(source) + ": " + m;
  } catch (const std::exception& e) {
    *message = std::string(source) + ": Gmsh failed: " + e.what();
  } catch (...) {
    *message = std::string(source) + ": Gmsh failed to read the file";
  }
  return kGmshReadInputError;
}
