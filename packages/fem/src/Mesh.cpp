#include "cms/fem/Mesh.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <new>
#include <set>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <utility>

#include <gmsh.h>

#include "cms/core/Error.hpp"
#include "MshStructureCheck.hpp"

namespace cms::fem {

const char* cellTypeName(CellType type) {
  switch (type) {
    case CellType::Point1: return "Point1";
    case CellType::Line2: return "Line2";
    case CellType::Line3: return "Line3";
    case CellType::Tri3: return "Tri3";
    case CellType::Tri6: return "Tri6";
    case CellType::Quad4: return "Quad4";
    case CellType::Tet4: return "Tet4";
    case CellType::Tet10: return "Tet10";
    case CellType::Hex8: return "Hex8";
    case CellType::Other: return "Other";
  }
  return "Other";
}

int cellNodeCount(CellType type) {
  switch (type) {
    case CellType::Point1: return 1;
    case CellType::Line2: return 2;
    case CellType::Line3: return 3;
    case CellType::Tri3: return 3;
    case CellType::Tri6: return 6;
    case CellType::Quad4: return 4;
    case CellType::Tet4: return 4;
    case CellType::Tet10: return 10;
    case CellType::Hex8: return 8;
    case CellType::Other: return 0;
  }
  return 0;
}

const PhysicalGroup& Mesh::group(const std::string& name) const {
  for (const PhysicalGroup& g : groups)
    if (g.name == name) return g;
  std::string available;
  for (const PhysicalGroup& g : groups) available += (available.empty() ? "\"" : ", \"") + g.name + "\"";
  throw InputError(source + ": no physical group named \"" + name + "\" (the mesh has " +
                   (available.empty() ? std::string("none") : available) + ")");
}

bool Mesh::hasGroup(const std::string& name) const {
  return std::any_of(groups.begin(), groups.end(),
                     [&](const PhysicalGroup& g) { return g.name == name; });
}

std::vector<std::int64_t> Mesh::nodeSet(const std::string& name) const {
  const PhysicalGroup& g = group(name);
  std::vector<std::int64_t> nodes;
  for (const CellBlock& b : g.blocks) nodes.insert(nodes.end(), b.nodes.begin(), b.nodes.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

namespace {

std::string readFile(const std::string& path) {
  std::error_code ec;
  CMS_INPUT_CHECK(!std::filesystem::exists(path, ec), path << ": cannot open the file (it does not exist)");
  // A directory or device would report a meaningless size.
  CMS_INPUT_CHECK(!std::filesystem::is_regular_file(path, ec), path << ": not a regular file");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  CMS_INPUT_CHECK(!in, path << ": cannot open the file");
  const std::streamoff size = in.tellg();
  CMS_INPUT_CHECK(size < 0, path << ": cannot read the file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  CMS_INPUT_CHECK(in.gcount() != size, path << ": cannot read the file");
  return bytes;
}

bool endsWith(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i]) return false;
  return true;
}

// ---------------------------------------------------------------------------
// Gmsh session and the mesh read through it.
// ---------------------------------------------------------------------------

/// Gmsh's SDK is one global state: initialise it for one read (which resets
/// every option a previous .geo script set) and always finalise it, also
/// when the read throws. The ONELAB parameters survive finalize(): without
/// clearing them, a script's DefineConstant takes the value a previous
/// script gave a parameter of the same name instead of its own default.
/// (Each initialize/finalize pair leaks a little in Gmsh 4.8, growing with
/// the number of pairs: ~55 MB after 2000 reads; nothing for the handful of
/// reads of a normal run. Keeping one session instead would let options
/// leak from one script into the next, and 4.8 cannot restore defaults.)
class GmshSession {
public:
  GmshSession() {
    gmsh::initialize(0, nullptr, false);  // no gmshrc / gmsh-options from the user's home
    active_ = true;
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::logger::start();  // for the first error of a script (see firstError)
    gmsh::onelab::clear();
    // MSH 2 periodic links are not read (the Mesh has no use for them, and
    // the scan above does not validate them): Gmsh's default, made explicit.
    gmsh::option::setNumber("Mesh.IgnorePeriodicity", 1);
  }
  ~GmshSession() {
    if (!active_) return;
    try {
      gmsh::logger::stop();  // and clear: the log outlives finalize()
      gmsh::onelab::clear();
      gmsh::finalize();
    } catch (...) {
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

private:
  bool active_ = false;
};

CellType cellType(int gmshType) {
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

/// Two distinct nodes closer than 1e-9 of the bounding-box diagonal are an
/// unmerged geometry (coincident faces meshed twice), which would leave the
/// parts unconnected. Cells of that size, sorted, each compared with itself
/// and its 13 lexicographically later neighbours, the neighbours found by
/// one forward sweep per offset: O(n log n). Long double keeps the extent of
/// coordinates near +-1e308 finite.
void checkDistinctNodes(const Mesh& mesh) {
  const std::size_t n = mesh.nodeCount();
  if (n < 2) return;
  long double lo[3], hi[3];
  for (int c = 0; c < 3; ++c) lo[c] = hi[c] = mesh.coordinates[c];
  for (std::size_t i = 1; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min<long double>(lo[c], mesh.coordinates[3 * i + c]);
      hi[c] = std::max<long double>(hi[c], mesh.coordinates[3 * i + c]);
    }
  long double diag2 = 0;
  for (int c = 0; c < 3; ++c) diag2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
  const long double diag = std::sqrt(diag2), tol = 1e-9L * diag;
  auto report = [&](std::size_t a, std::size_t b, long double d) {
    if (mesh.nodeTags[a] > mesh.nodeTags[b]) std::swap(a, b);
    CMS_INPUT_CHECK(true, mesh.source << ": nodes " << mesh.nodeTags[a] << " and " << mesh.nodeTags[b]
                                      << " coincide (distance " << static_cast<double>(d)
                                      << ", below 1e-9 of the mesh size " << static_cast<double>(diag)
                                      << "): an unmerged geometry?");
  };
  if (tol == 0) report(0, 1, 0);

  struct Item {
    std::int64_t key[3];
    std::size_t node;
  };
  std::vector<Item> items(n);
  for (std::size_t i = 0; i < n; ++i) {
    items[i].node = i;
    for (int c = 0; c < 3; ++c)
      items[i].key[c] = static_cast<std::int64_t>(std::floor((mesh.coordinates[3 * i + c] - lo[c]) / tol));
  }
  auto less = [](const std::int64_t* a, const std::int64_t* b) {
    return std::lexicographical_compare(a, a + 3, b, b + 3);
  };
  std::sort(items.begin(), items.end(), [&](const Item& a, const Item& b) { return less(a.key, b.key); });
  struct Cell {
    std::int64_t key[3];
    std::size_t begin, end;
  };
  std::vector<Cell> cells;
  for (std::size_t i = 0; i < n; ++i) {
    if (cells.empty() || !std::equal(items[i].key, items[i].key + 3, cells.back().key))
      cells.push_back({{items[i].key[0], items[i].key[1], items[i].key[2]}, i, i});
    cells.back().end = i + 1;
  }
  auto close = [&](std::size_t a, std::size_t b) {
    long double d2 = 0;
    for (int c = 0; c < 3; ++c) {
      const long double d = static_cast<long double>(mesh.coordinates[3 * a + c]) - mesh.coordinates[3 * b + c];
      d2 += d * d;
    }
    if (d2 <= tol * tol) report(a, b, std::sqrt(d2));
  };
  std::vector<std::array<int, 3>> offsets;
  for (int dx = 0; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (dx > 0 || dy > 0 || (dy == 0 && dz > 0)) offsets.push_back({dx, dy, dz});
  std::vector<std::size_t> cursor(offsets.size(), 0);
  for (const Cell& cell : cells) {
    for (std::size_t i = cell.begin; i < cell.end; ++i)
      for (std::size_t j = i + 1; j < cell.end; ++j) close(items[i].node, items[j].node);
    for (std::size_t o = 0; o < offsets.size(); ++o) {
      const std::int64_t target[3] = {cell.key[0] + offsets[o][0], cell.key[1] + offsets[o][1],
                                      cell.key[2] + offsets[o][2]};
      std::size_t& k = cursor[o];
      while (k < cells.size() && less(cells[k].key, target)) ++k;
      if (k == cells.size() || !std::equal(target, target + 3, cells[k].key)) continue;
      for (std::size_t i = cell.begin; i < cell.end; ++i)
        for (std::size_t j = cells[k].begin; j < cells[k].end; ++j) close(items[i].node, items[j].node);
    }
  }
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
          block.type = cellType(types[t]);
          block.nodesPerCell = static_cast<int>(nodeTags[t].size() / elementTags[t].size());
          g.blocks.push_back(std::move(block));
        }
        CellBlock& block = g.blocks[b->second];
        const std::size_t npc = static_cast<std::size_t>(block.nodesPerCell);
        CMS_INPUT_CHECK(npc == 0 || nodeTags[t].size() != npc * elementTags[t].size(),
                        mesh.source << ": element block of type " << types[t] << " in physical group \""
                                    << g.name << "\" has inconsistent node counts");
        for (std::size_t e = 0; e < elementTags[t].size(); ++e) {
          block.cellTags.push_back(elementTags[t][e]);
          for (std::size_t k = 0; k < npc; ++k) {
            const std::size_t nodeTag = nodeTags[t][e * npc + k];
            const std::int64_t i = index(nodeTag);
            CMS_INPUT_CHECK(i < 0, mesh.source << ": element " << elementTags[t][e] << " refers to node "
                                               << nodeTag << ", which is not in the mesh");
            block.nodes.push_back(i);
          }
        }
      }
    }
    CMS_INPUT_CHECK(g.blocks.empty(), mesh.source << ": physical group \"" << g.name << "\" (dimension "
                                                  << dim << ", tag " << tag << ") has no cells");
    mesh.groups.push_back(std::move(g));
  }
}

/// The first error Gmsh logged in this session, without its "Error" tag:
/// a script's parser goes on after a syntax error, and its last message
/// (what it throws) is often "line 0: syntax error" at the end of the file.
std::string firstError() {
  std::vector<std::string> log;
  try {
    gmsh::logger::get(log);
  } catch (...) {
    return {};
  }
  for (const auto& l : log)
    if (l.compare(0, 5, "Error") == 0) {
      const std::size_t colon = l.find(':');
      return colon == std::string::npos ? l : l.substr(l.find_first_not_of(' ', colon + 1));
    }
  return {};
}

Mesh readThroughGmsh(const std::string& path, bool script, const std::map<std::string, double>& parameters) {
  if (script)
    for (const auto& [name, value] : parameters) gmsh::onelab::setNumber("Parameters/" + name, {value});
  gmsh::open(path);
  if (script) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elementTags, nodeTags;
    gmsh::model::mesh::getElements(types, elementTags, nodeTags);
    if (types.empty()) {
      gmsh::vectorpair entities;
      gmsh::model::getEntities(entities);
      int dim = -1;
      for (const auto& e : entities) dim = std::max(dim, e.first);
      // A point at an infinite coordinate (1e309 in the script) aborts
      // Gmsh 4.8's mesher (SIGABRT, found by the fuzz driver): named first.
      for (const auto& [d, tag] : entities) {
        if (d != 0) continue;
        std::vector<double> x;
        gmsh::model::getValue(0, tag, {}, x);
        for (double v : x)
          CMS_INPUT_CHECK(!std::isfinite(v), path << ": point " << tag << " has a non-finite coordinate (" << v << ")");
      }
      if (dim >= 0) {
        // Gmsh 4.8 throws its meshing errors from inside OpenMP regions,
        // which ends the process (std::terminate: a plane surface made
        // non-planar, found by the fuzz driver). Meshing with errors
        // logged instead (and no "Continue?" prompt on the terminal), the
        // first one is the input error.
        double abortOnError = 0, expertMode = 0;
        gmsh::option::getNumber("General.AbortOnError", abortOnError);
        gmsh::option::getNumber("General.ExpertMode", expertMode);
        gmsh::option::setNumber("General.AbortOnError", 0);
        gmsh::option::setNumber("General.ExpertMode", 1);
        gmsh::model::mesh::generate(dim);
        gmsh::option::setNumber("General.AbortOnError", abortOnError);
        gmsh::option::setNumber("General.ExpertMode", expertMode);
        const std::string error = firstError();
        CMS_INPUT_CHECK(!error.empty(), path << ": meshing failed: " << error);
      }
    }
  }
  Mesh mesh;
  mesh.source = path;
  readNodes(mesh);
  checkDistinctNodes(mesh);
  readGroups(mesh);
  return mesh;
}

}  // namespace

Mesh readGmsh(const std::string& path, const std::map<std::string, double>& parameters) {
  bool script = false;
  {
    const std::string bytes = readFile(path);
    if (bytes.compare(0, 11, "$MeshFormat") == 0) {
      detail::checkMshStructure(path, bytes);
    } else {
      script = endsWith(path, ".geo");
      CMS_INPUT_CHECK(!script, path << ": not a Gmsh mesh (a .msh file starts with $MeshFormat) nor a "
                                       ".geo script");
    }
  }
  try {
    GmshSession session;
    try {
      return readThroughGmsh(path, script, parameters);
    } catch (const InputError&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::string& message) {  // how Gmsh 4.8 raises its errors
      const std::string first = firstError();
      throw InputError(path + ": " + (first.empty() ? message : first));
    } catch (...) {
      // Read Gmsh's message while the session that raised it is still open.
      std::string message = firstError();
      try {
        if (message.empty()) gmsh::logger::getLastError(message);
      } catch (...) {
      }
      if (!message.empty()) throw InputError(path + ": " + message);
      throw;
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    // Past the scan no count in the file drives an allocation: running out
    // of memory is the machine's limit, not malformed input.
    throw;
  } catch (const std::string& message) {  // from initialize / finalize
    throw InputError(path + ": " + message);
  } catch (const std::exception& e) {
    throw InputError(path + ": Gmsh failed: " + e.what());
  } catch (...) {
    throw InputError(path + ": Gmsh failed to read the file");
  }
}

}  // namespace cms::fem
