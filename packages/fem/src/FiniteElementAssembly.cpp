// Parallel assembly (doc/architecture.md, "fem"; doc/theory.md §9-§10).
//
// Ownership: rows belong to the ranks of a coordinate-slab partition of the
// nodes, elements ("items": frames, solids, point masses, springs) to the
// rank owning their first node; the numbering (mesh order) is independent of
// the rank count and rows shared between ranks occur only at slab
// interfaces. All matrices share one sparsity pattern, built (with the
// exchange of its ghost rows) before any value is computed; element values
// go straight into the final owned arrays, and only ghost rows travel.

#include "cms/fem/FiniteElementAssembly.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/fem/FrameElement.hpp"
#include "cms/fem/LumpedElements.hpp"
#include "cms/fem/SolidElement.hpp"

namespace cms::fem {

namespace {

constexpr std::uint8_t kTranslations = 0x07;
constexpr std::uint8_t kAllComponents = 0x3f;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// One contribution to the matrices: an element of a set, or a lumped item.
struct Item {
  enum class Kind : std::uint8_t { Frame, Solid, PointMass, GroundSpring, Spring };
  Kind kind;
  int set;                 ///< index into the model's sets of that kind
  const CellBlock* block;  ///< Frame, Solid
  std::int64_t cell;       ///< Frame, Solid: cell index; lumped: first node
  std::int64_t other;      ///< Spring: second node
};

SolidType solidTypeOf(CellType t) {
  switch (t) {
    case CellType::Tet4: return SolidType::Tet4;
    case CellType::Tet10: return SolidType::Tet10;
    default: return SolidType::Hex8;
  }
}

std::string nodeName(const Mesh& mesh, std::int64_t node) {
  return "node " + std::to_string(mesh.nodeTags[node]);
}

/// Nodes of a and b paired by coincident coordinates (a joint between two
/// coincident node sets), or the single pair when both hold one node.
std::vector<std::pair<std::int64_t, std::int64_t>> springPairs(const Mesh& mesh,
                                                               const SpringSet& s) {
  const auto a = mesh.nodeSet(s.nodeSet), b = mesh.nodeSet(s.toNodeSet);
  std::vector<std::pair<std::int64_t, std::int64_t>> pairs;
  if (a.size() == 1 && b.size() == 1) return {{a[0], b[0]}};
  CMS_INPUT_CHECK(a.size() != b.size(),
                  "spring '" << s.name << "': node sets '" << s.nodeSet << "' (" << a.size()
                             << " nodes) and '" << s.toNodeSet << "' (" << b.size()
                             << " nodes) must have the same size to be paired");
  double scale = 0.0;
  for (std::size_t i = 0; i < mesh.coordinates.size(); ++i)
    scale = std::max(scale, std::abs(mesh.coordinates[i]));
  const double tol = 1e-9 * std::max(scale, 1.0);
  for (std::int64_t na : a) {
    std::int64_t match = -1;
    for (std::int64_t nb : b) {
      double d = 0.0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(mesh.x(na)[c] - mesh.x(nb)[c]));
      if (d <= tol) { match = nb; break; }
    }
    CMS_INPUT_CHECK(match < 0, "spring '" << s.name << "': " << nodeName(mesh, na) << " of set '"
                                          << s.nodeSet << "' has no coincident node in set '"
                                          << s.toNodeSet << "'");
    pairs.emplace_back(na, match);
  }
  return pairs;
}

bool hasRotationalStiffness(const std::array<double, 6>& k) {
  return k[3] != 0.0 || k[4] != 0.0 || k[5] != 0.0;
}

/// The element DOF components of one node for an item: frames and 6-DOF
/// lumped items use all six, solids and 3-DOF lumped items the translations.
int itemNodeDofs(const Item& it, const FiniteElementModel& model) {
  switch (it.kind) {
    case Item::Kind::Frame: return 6;
    case Item::Kind::Solid: return 3;
    case Item::Kind::PointMass: {
      const auto& p = model.pointMasses[it.set];
      return std::any_of(p.inertia.begin(), p.inertia.end(), [](double v) { return v != 0.0; }) ? 6 : 3;
    }
    default: return hasRotationalStiffness(model.springs[it.set].stiffness) ? 6 : 3;
  }
}

/// The item's element matrices (only those the model needs) in a fixed order.
struct ItemMatrices {
  ElementMatrix M, K;
  SpinMatrices spin;  ///< G1, KT1, f1 (empty when no spin)
};

}  // namespace

int DofLayout::componentCount(std::int64_t node) const {
  return __builtin_popcount(present[node] & ~fixed[node]);
}

long long DofLayout::row(std::int64_t node, Component c) const {
  const int bit = static_cast<int>(c);
  const std::uint8_t free = present[node] & ~fixed[node];
  if (!(free & (1u << bit))) return -1;
  return first[node] + __builtin_popcount(free & ((1u << bit) - 1u));
}

AssembledMatrices assemble(const FiniteElementModel& model,
                           const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                           const PrestressConditions& prestress) {
  const auto t0 = std::chrono::steady_clock::now();
  model.validate();
  const Mesh& mesh = *model.mesh;
  const std::int64_t numNodes = static_cast<std::int64_t>(mesh.nodeCount());
  const int rank = comm->getRank(), nranks = comm->getSize();

  // 1. Items, in set order: the same list on every rank.
  std::vector<Item> items;
  for (std::size_t s = 0; s < model.elementSets.size(); ++s) {
    const auto& set = model.elementSets[s];
    const auto kind = set.kind == ElementSet::Kind::Frame ? Item::Kind::Frame : Item::Kind::Solid;
    for (const CellBlock& b : mesh.group(set.group).blocks)
      for (std::size_t c = 0; c < b.size(); ++c)
        items.push_back({kind, static_cast<int>(s), &b, static_cast<std::int64_t>(c), -1});
  }
  const std::size_t numElements = items.size();
  for (std::size_t s = 0; s < model.pointMasses.size(); ++s)
    for (std::int64_t n : mesh.nodeSet(model.pointMasses[s].nodeSet))
      items.push_back({Item::Kind::PointMass, static_cast<int>(s), nullptr, n, -1});
  for (std::size_t s = 0; s < model.springs.size(); ++s) {
    const auto& sp = model.springs[s];
    if (sp.toNodeSet.empty()) {
      for (std::int64_t n : mesh.nodeSet(sp.nodeSet))
        items.push_back({Item::Kind::GroundSpring, static_cast<int>(s), nullptr, n, -1});
    } else {
      for (auto [a, b] : springPairs(mesh, sp))
        items.push_back({Item::Kind::Spring, static_cast<int>(s), nullptr, a, b});
    }
  }

  auto itemNodes = [&](const Item& it, std::int64_t* out) -> int {
    if (it.block) {
      const int n = it.block->nodesPerCell;
      std::copy_n(&it.block->nodes[it.cell * n], n, out);
      return n;
    }
    out[0] = it.cell;
    if (it.kind == Item::Kind::Spring) { out[1] = it.other; return 2; }
    return 1;
  };

  // 2. Components per node (doc/architecture.md, "DOF layout").
  AssembledMatrices out;
  DofLayout& L = out.layout;
  L.present.assign(numNodes, 0);
  L.fixed.assign(numNodes, 0);
  std::int64_t nodes[32];
  for (const Item& it : items) {
    if (it.kind != Item::Kind::Frame && it.kind != Item::Kind::Solid) continue;
    const int nn = itemNodes(it, nodes);
    for (int a = 0; a < nn; ++a)
      L.present[nodes[a]] |= it.kind == Item::Kind::Frame ? kAllComponents : kTranslations;
  }
  for (const Item& it : items) {
    if (it.kind == Item::Kind::Frame || it.kind == Item::Kind::Solid) continue;
    const int nn = itemNodes(it, nodes);
    const bool rotations = itemNodeDofs(it, model) == 6;
    const std::string& name =
        it.kind == Item::Kind::PointMass ? model.pointMasses[it.set].name : model.springs[it.set].name;
    for (int a = 0; a < nn; ++a) {
      CMS_INPUT_CHECK(rotations && (L.present[nodes[a]] & kAllComponents) != kAllComponents,
                      model.name << ": " << (it.kind == Item::Kind::PointMass ? "point mass '" : "spring '")
                                 << name << "' acts on the rotations of " << nodeName(mesh, nodes[a])
                                 << ", which has none (only nodes of frame elements do)");
      L.present[nodes[a]] |= kTranslations;
    }
  }
  {
    std::vector<std::size_t> loose;
    for (std::int64_t n = 0; n < numNodes; ++n)
      if (!L.present[n]) loose.push_back(mesh.nodeTags[n]);
    if (!loose.empty()) {
      std::ostringstream os;
      os << mesh.source << ": " << loose.size()
         << " node(s) belong to no element set or lumped item (unconnected), e.g. node";
      for (std::size_t i = 0; i < std::min<std::size_t>(loose.size(), 5); ++i) os << ' ' << loose[i];
      os << "; add their physical group to an element set or remove them from the mesh";
      throw InputError(os.str());
    }
  }
  for (const FixedSet& f : model.fixed) {
    for (std::int64_t n : mesh.nodeSet(f.nodeSet)) {
      if (f.all) { L.fixed[n] |= L.present[n]; continue; }
      for (Component c : f.components) {
        const std::uint8_t bit = 1u << static_cast<int>(c);
        CMS_INPUT_CHECK(!(L.present[n] & bit), "boundary condition '" << f.name << "' fixes "
                                                   << componentName(c) << " at " << nodeName(mesh, n)
                                                   << ", which has no such DOF");
        L.fixed[n] |= bit;
      }
    }
  }
  L.first.assign(numNodes, 0);
  long long next = 0;
  for (std::int64_t n = 0; n < numNodes; ++n) {
    L.first[n] = next;
    next += L.componentCount(n);
  }
  L.size = next;
  CMS_INPUT_CHECK(L.size == 0, model.name << ": every DOF is fixed; nothing to assemble");

  // 3. Ownership: a coordinate-slab partition of the nodes (sorted along the
  // mesh's longest extent, cut into equal counts), whose rows each rank owns;
  // an item belongs to the rank owning its first node, so rows shared between
  // ranks occur only at the slab interfaces. Gmsh numbers boundary entities'
  // nodes first, so blocks of node numbers were not compact: 14% of the rows
  // were ghosts on 2 ranks (doc/benchmarks.md, "Assembly"). Rows keep the
  // mesh-order numbering, so matrices do not depend on the rank count.
  using GO = GlobalOrdinal;
  using LO = LocalOrdinal;
  std::vector<int> owner(numNodes, 0);
  if (nranks > 1) {
    int axis = 0;
    double extent[3];
    for (int c = 0; c < 3; ++c) {
      double lo = mesh.x(0)[c], hi = lo;
      for (std::int64_t n = 1; n < numNodes; ++n) {
        lo = std::min(lo, mesh.x(n)[c]);
        hi = std::max(hi, mesh.x(n)[c]);
      }
      extent[c] = hi - lo;
      if (extent[c] > extent[axis]) axis = c;
    }
    std::vector<std::int64_t> order(numNodes);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
      return mesh.x(a)[axis] < mesh.x(b)[axis];
    });
    for (std::int64_t k = 0; k < numNodes; ++k) owner[order[k]] = static_cast<int>(k * nranks / numNodes);
  }
  std::vector<std::size_t> localItems;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::int64_t n0 = items[i].block ? items[i].block->nodes[items[i].cell * items[i].block->nodesPerCell]
                                           : items[i].cell;
    if (owner[n0] == rank) localItems.push_back(i);
  }
  std::vector<GO> overlapGids;
  for (std::int64_t n = 0; n < numNodes; ++n)
    if (owner[n] == rank)
      for (int c = 0; c < L.componentCount(n); ++c) overlapGids.push_back(static_cast<GO>(L.first[n] + c));
  const LO numOwned = static_cast<LO>(overlapGids.size());
  auto ownedMap = Teuchos::rcp(new Map(static_cast<GO>(L.size), Teuchos::ArrayView<const GO>(overlapGids), 0, comm));

  // 4. Each item's global rows (-1 for fixed), then the overlap map: owned
  // rows first, then the ghost rows in ascending order.
  std::vector<std::int64_t> itemDofStart(localItems.size() + 1, 0);
  std::vector<long long> itemDofs;
  for (std::size_t k = 0; k < localItems.size(); ++k) {
    const Item& it = items[localItems[k]];
    const int nn = itemNodes(it, nodes), nd = itemNodeDofs(it, model);
    for (int a = 0; a < nn; ++a)
      for (int c = 0; c < nd; ++c) itemDofs.push_back(L.row(nodes[a], static_cast<Component>(c)));
    itemDofStart[k + 1] = static_cast<std::int64_t>(itemDofs.size());
  }
  std::vector<LO> rowLid(L.size, -1);  // global row -> overlap lid (one int per row: 4 MB at 10^6)
  for (LO l = 0; l < numOwned; ++l) rowLid[overlapGids[l]] = l;
  std::vector<long long> ghosts;
  for (long long g : itemDofs)
    if (g >= 0 && rowLid[g] < 0) ghosts.push_back(g);
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  const LO numOverlap = numOwned + static_cast<LO>(ghosts.size());
  for (std::size_t k = 0; k < ghosts.size(); ++k) {
    rowLid[ghosts[k]] = numOwned + static_cast<LO>(k);
    overlapGids.push_back(static_cast<GO>(ghosts[k]));
  }
  auto overlapMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                         Teuchos::ArrayView<const GO>(overlapGids), 0, comm));
  std::vector<LO> itemLids(itemDofs.size());
  std::transform(itemDofs.begin(), itemDofs.end(), itemLids.begin(),
                 [&](long long g) { return g < 0 ? LO(-1) : rowLid[g]; });

  // 5. The shared CSR pattern over the overlap rows (columns: overlap lids).
  Teuchos::ArrayRCP<std::size_t> rowPtr(numOverlap + 1, 0);
  for (std::size_t i = 0; i + 1 < itemDofStart.size(); ++i) {
    const auto b = itemDofStart[i], e = itemDofStart[i + 1];
    for (auto p = b; p < e; ++p)
      if (itemLids[p] >= 0) rowPtr[itemLids[p] + 1] += static_cast<std::size_t>(e - b);
  }
  for (LO r = 0; r < numOverlap; ++r) rowPtr[r + 1] += rowPtr[r];
  std::vector<LO> cols(rowPtr[numOverlap]);
  {
    std::vector<std::size_t> fill(rowPtr.begin(), rowPtr.end() - 1);
    for (std::size_t i = 0; i + 1 < itemDofStart.size(); ++i) {
      const auto b = itemDofStart[i], e = itemDofStart[i + 1];
      for (auto p = b; p < e; ++p) {
        if (itemLids[p] < 0) continue;
        for (auto q = b; q < e; ++q)
          if (itemLids[q] >= 0) cols[fill[itemLids[p]]++] = itemLids[q];
      }
    }
  }
  // Sort and deduplicate each row in place, compacting the arrays.
  std::size_t write = 0;
  for (LO r = 0; r < numOverlap; ++r) {
    const std::size_t b = rowPtr[r], e = rowPtr[r + 1];
    std::sort(cols.begin() + b, cols.begin() + e);
    const std::size_t start = write;
    for (std::size_t p = b; p < e; ++p)
      if (p == b || cols[p] != cols[p - 1]) cols[write++] = cols[p];
    rowPtr[r] = start;
  }
  rowPtr[numOverlap] = write;
  cols.resize(write);
  cols.shrink_to_fit();

  // 6. The owned pattern, before any value is computed. Only the ghost rows
  // (a slab interface) cross ranks: their pattern is exported once and
  // merged into the owned rows' own pattern locally; element values are then
  // scattered straight into the owned rows' final arrays and a small ghost
  // array, which an Export (ADD) sends to the owners. Exporting every matrix
  // whole with Tpetra's exportAndFillComplete, or even just the whole
  // pattern, cost more than the element loop at 10^6 DOFs
  // (doc/benchmarks.md, "Assembly").
  Tpetra::Export<> exporter(overlapMap, ownedMap);
  using Graph = Tpetra::CrsGraph<>;
  auto ghostMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                       Teuchos::ArrayView<const GO>(ghosts.empty() ? nullptr : overlapGids.data() + numOwned,
                                                                    ghosts.size()),
                                       0, comm));
  const std::size_t ghostBegin = rowPtr[numOwned];
  Teuchos::RCP<const Graph> ghostGraph;
  {
    Teuchos::ArrayRCP<std::size_t> ghostRowPtr(ghosts.size() + 1);
    for (std::size_t r = 0; r <= ghosts.size(); ++r) ghostRowPtr[r] = rowPtr[numOwned + r] - ghostBegin;
    Teuchos::ArrayRCP<LO> ghostCols(cols.size() - ghostBegin);
    std::copy(cols.begin() + ghostBegin, cols.end(), ghostCols.begin());
    auto g = Teuchos::rcp(new Graph(ghostMap, overlapMap, ghostRowPtr, ghostCols));
    g->expertStaticFillComplete(ownedMap, ownedMap);
    ghostGraph = g;
  }
  Tpetra::Export<> ghostExporter(ghostMap, ownedMap);
  // The owned pattern: columns numbered as in the overlap map (so an owned
  // row's own entries keep their column lids), then the columns only other
  // ranks' elements bring, appended.
  Teuchos::ArrayRCP<std::size_t> ownedRowPtr(numOwned + 1, 0);
  std::vector<LO> ownedCols;
  std::vector<GO> colGids(overlapGids);
  {
    const auto received = Tpetra::exportAndFillCompleteCrsGraph<Graph>(ghostGraph, ghostExporter, ownedMap, ownedMap);
    const auto rec = received->getLocalGraphHost();
    const auto& recCols = *received->getColMap();
    std::unordered_map<GO, LO> extra;
    ownedCols.reserve(ghostBegin + rec.entries.extent(0));
    for (LO r = 0; r < numOwned; ++r) {
      const std::size_t start = ownedCols.size();
      ownedCols.insert(ownedCols.end(), cols.begin() + rowPtr[r], cols.begin() + rowPtr[r + 1]);
      const std::size_t rb = rec.row_map(r), re = rec.row_map(r + 1);
      for (std::size_t p = rb; p < re; ++p) {
        const GO g = recCols.getGlobalElement(rec.entries(p));
        LO l = g < static_cast<GO>(rowLid.size()) ? rowLid[g] : -1;
        if (l < 0) {
          auto [it, fresh] = extra.emplace(g, static_cast<LO>(colGids.size()));
          if (fresh) colGids.push_back(g);
          l = it->second;
        }
        ownedCols.push_back(l);
      }
      if (re > rb) {
        std::sort(ownedCols.begin() + start, ownedCols.end());
        ownedCols.erase(std::unique(ownedCols.begin() + start, ownedCols.end()), ownedCols.end());
      }
      ownedRowPtr[r + 1] = ownedCols.size();
    }
  }
  std::vector<LO>().swap(rowLid);
  auto colMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                     Teuchos::ArrayView<const GO>(colGids), 0, comm));
  const std::size_t ownedNnz = ownedCols.size();
  Teuchos::RCP<const Graph> ownedGraph;
  {
    Teuchos::ArrayRCP<LO> c(ownedNnz);
    std::copy(ownedCols.begin(), ownedCols.end(), c.begin());
    std::vector<LO>().swap(ownedCols);
    auto g = Teuchos::rcp(new Graph(ownedMap, colMap, ownedRowPtr, c));
    g->expertStaticFillComplete(ownedMap, ownedMap);
    ownedGraph = g;
  }

  // Positions of an item's entries: found once per item (a binary search per
  // entry) and reused by every matrix of that item. p >= 0: entry p of the
  // owned arrays; p <= -2: entry -p-2 of the ghost arrays; -1: fixed DOF.
  const auto owned = ownedGraph->getLocalGraphHost();
  std::vector<std::int64_t> positions;
  auto locate = [&](std::size_t local) {
    const auto b = itemDofStart[local], e = itemDofStart[local + 1];
    const int n = static_cast<int>(e - b);
    positions.assign(static_cast<std::size_t>(n) * n, -1);
    for (int i = 0; i < n; ++i) {
      const LO r = itemLids[b + i];
      if (r < 0) continue;
      const bool mine = r < numOwned;
      const LO* base = mine ? owned.entries.data() : cols.data();
      const LO* rb = base + (mine ? owned.row_map(r) : rowPtr[r]);
      const LO* re = base + (mine ? owned.row_map(r + 1) : rowPtr[r + 1]);
      for (int j = 0; j < n; ++j) {
        const LO c = itemLids[b + j];
        if (c < 0) continue;
        const std::int64_t at = std::lower_bound(rb, re, c) - base;
        positions[static_cast<std::size_t>(i) * n + j] =
            mine ? at : -2 - (at - static_cast<std::int64_t>(ghostBegin));
      }
    }
  };
  using Values = CrsMatrix::local_matrix_device_type::values_type;  // host memory (Serial node)
  struct Target {
    Values owned, ghost;
  };
  auto target = [&](const char* name) {
    return Target{Values(std::string(name) + " owned", ownedNnz), Values(std::string(name) + " ghost", cols.size() - ghostBegin)};
  };
  auto scatter = [&](const ElementMatrix& A, Target& t) {
    const std::size_t nn = positions.size();
    for (std::size_t k = 0; k < nn; ++k) {
      const std::int64_t p = positions[k];
      if (p >= 0) t.owned(p) += A.a[k];
      else if (p <= -2) t.ghost(-2 - p) += A.a[k];
    }
  };
  auto scatterVector = [&](std::size_t local, const std::vector<double>& f, std::vector<double>& v) {
    const auto b = itemDofStart[local], e = itemDofStart[local + 1];
    for (auto p = b; p < e; ++p)
      if (itemLids[p] >= 0) v[itemLids[p]] += f[p - b];
  };

  out.setupSeconds = secondsSince(t0);
  out.localItems = static_cast<long long>(localItems.size());
  out.ghostRows = static_cast<long long>(ghosts.size());
  const auto tElements = std::chrono::steady_clock::now();
  // 7. Element matrices. Errors are collected and reduced so every rank
  // throws together (a rank's own elements may be the only bad ones).
  const bool spinning = model.spin.has_value();
  const bool rotatingFrame = spinning && model.spin->frame == SpinDefinition::Frame::Rotating;
  const Spin spin = spinning ? model.spin->spin : Spin{};
  Target vM = target("M"), vK = target("K"), vG, vKT;
  std::vector<double> vf;
  if (spinning) vG = target("G1");
  const bool tilt = spinning && !rotatingFrame && model.spin->frameAxis.has_value();
  if (rotatingFrame) { vKT = target("KT1"); vf.assign(numOverlap, 0.0); }
  if (tilt) vKT = target("KX1");

  auto frameOf = [&](const Item& it) {
    const auto& set = model.elementSets[it.set];
    FrameElement fe;
    const std::int64_t* cn = &it.block->nodes[it.cell * it.block->nodesPerCell];
    std::copy_n(mesh.x(cn[0]), 3, fe.x1.begin());
    std::copy_n(mesh.x(cn[1]), 3, fe.x2.begin());
    fe.material = model.materials.at(set.material);
    fe.section = set.section;
    fe.theory = set.theory;
    return fe;
  };
  std::vector<double> xyz(3 * 27);
  auto solidOf = [&](const Item& it) {
    const auto& set = model.elementSets[it.set];
    const std::int64_t* cn = &it.block->nodes[it.cell * it.block->nodesPerCell];
    for (int a = 0; a < it.block->nodesPerCell; ++a) std::copy_n(mesh.x(cn[a]), 3, &xyz[3 * a]);
    return SolidElement{solidTypeOf(it.block->type), xyz.data(), model.materials.at(set.material)};
  };
  auto pointMassOf = [&](const Item& it) {
    PointMass p;
    p.m = model.pointMasses[it.set].mass;
    p.inertia = model.pointMasses[it.set].inertia;
    std::copy_n(mesh.x(it.cell), 3, p.x.begin());
    return p;
  };

  std::string failure;
  bool failureIsInput = false;  // an element's data is bad, not the numerics
  for (std::size_t local = 0; local < localItems.size() && failure.empty(); ++local) {
    const Item& it = items[localItems[local]];
    const int nd = itemNodeDofs(it, model);
    try {
      ItemMatrices m;
      switch (it.kind) {
        case Item::Kind::Frame: {
          const FrameElement fe = frameOf(it);
          m.K = frameStiffness(fe);
          m.M = frameMass(fe);
          if (rotatingFrame) m.spin = frameSpinMatrices(fe, spin);
          else if (spinning) m.spin.G1 = frameStationaryGyroscopic(fe, spin.axis);
          if (tilt) m.spin.KT1 = frameStationaryTiltStiffness(fe, spin.axis, *model.spin->frameAxis);
          break;
        }
        case Item::Kind::Solid: {
          const SolidElement se = solidOf(it);
          m.K = solidStiffness(se);
          m.M = solidMass(se);
          if (rotatingFrame) m.spin = solidSpinMatrices(se, spin);
          break;
        }
        case Item::Kind::PointMass: {
          const PointMass p = pointMassOf(it);
          m.M = pointMassMatrix(p, nd);
          m.K = ElementMatrix(nd);
          if (rotatingFrame) m.spin = pointMassSpinMatrices(p, spin, nd);
          else if (spinning && nd == 6) m.spin.G1 = pointMassStationaryGyroscopic(p, spin.axis);
          if (tilt && nd == 6) m.spin.KT1 = pointMassStationaryTiltStiffness(p, spin.axis, *model.spin->frameAxis);
          break;
        }
        case Item::Kind::GroundSpring:
          m.K = groundedSpringMatrix(model.springs[it.set].stiffness, nd);
          break;
        case Item::Kind::Spring:
          m.K = twoNodeSpringMatrix(model.springs[it.set].stiffness, nd);
          break;
      }
      locate(local);
      scatter(m.K, vK);
      if (m.M.n) scatter(m.M, vM);
      if (m.spin.G1.n) scatter(m.spin.G1, vG);
      if ((rotatingFrame || tilt) && m.spin.KT1.n) scatter(m.spin.KT1, vKT);
      if (rotatingFrame && !m.spin.f1.empty()) scatterVector(local, m.spin.f1, vf);
    } catch (const std::exception& e) {
      std::ostringstream os;
      os << model.name << ": ";
      if (it.block) os << "element " << it.block->cellTags[it.cell] << " of set '"
                       << model.elementSets[it.set].group << "'";
      else os << nodeName(mesh, it.cell);
      os << ": " << e.what();
      failure = os.str();
      failureIsInput = dynamic_cast<const InputError*>(&e) != nullptr;
    }
  }
  auto throwIfAnyFailed = [&](const std::string& what) {
    int bad = what.empty() ? 0 : (failureIsInput ? 2 : 1), anyBad = 0;
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, bad, Teuchos::outArg(anyBad));
    if (!anyBad) return;
    // The message of the lowest failing rank, on every rank.
    int src = bad ? rank : nranks, lowest = 0;
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MIN, src, Teuchos::outArg(lowest));
    int len = static_cast<int>(what.size());
    Teuchos::broadcast(*comm, lowest, Teuchos::outArg(len));
    std::string msg = what;
    msg.resize(len);
    Teuchos::broadcast(*comm, lowest, len, msg.data());
    if (anyBad == 2) throw InputError(msg);
    throw NumericalError(msg);
  };
  throwIfAnyFailed(failure);
  out.elementSeconds = secondsSince(tElements);
  const auto tExport = std::chrono::steady_clock::now();

  auto finish = [&](Target& t) -> Teuchos::RCP<const CrsMatrix> {
    CrsMatrix ghost(ghostGraph, t.ghost);
    if (!ghost.isFillComplete()) ghost.fillComplete(ownedMap, ownedMap);
    auto A = Teuchos::rcp(new CrsMatrix(ownedGraph, t.owned));
    t = Target();
    A->resumeFill();
    A->doExport(ghost, ghostExporter, Tpetra::ADD);
    A->fillComplete(ownedMap, ownedMap);
    return A;
  };
  out.map = ownedMap;
  out.M = finish(vM);
  out.K = finish(vK);
  if (spinning) out.G1 = finish(vG);
  if (tilt) out.KX1 = finish(vKT);
  if (rotatingFrame) {
    out.KT1 = finish(vKT);
    MultiVector fOverlap(overlapMap, 1);
    {
      auto view = fOverlap.getDataNonConst(0);
      std::copy(vf.begin(), vf.end(), view.begin());
    }
    auto f1 = Teuchos::rcp(new MultiVector(ownedMap, 1));
    f1->doExport(fOverlap, exporter, Tpetra::ADD);
    out.f1 = f1;
  }
  out.elementCount = static_cast<long long>(numElements);
  out.exportSeconds = secondsSince(tExport);
  out.assemblySeconds = secondsSince(t0);

  // 8. Centrifugal prestress (theory §10): K u1 = f1 per unit Omega^2, then
  // the geometric stiffness of the element stresses of u1.
  CMS_INPUT_CHECK(!prestress.empty() && !(rotatingFrame && model.spin->stressStiffening),
                  model.name << ": prestress conditions given, but the model has no rotating-frame "
                                "spin with stress stiffening");
  if (rotatingFrame && model.spin->stressStiffening) {
    const auto t1 = std::chrono::steady_clock::now();
    // Held DOFs and children's loads (theory §10.2): rows resolved here,
    // where the layout is known. A held DOF the model already fixes has no
    // row and needs no hold.
    auto rowOf = [&](const PrestressConditions::NodalValue& v, const char* what) {
      CMS_INPUT_CHECK(v.node < 0 || v.node >= numNodes,
                      model.name << ": prestress " << what << " at node index " << v.node << " (mesh has "
                                 << numNodes << " nodes)");
      CMS_INPUT_CHECK(!(L.present[v.node] & (1u << static_cast<int>(v.component))),
                      model.name << ": prestress " << what << " on " << componentName(v.component) << " at "
                                 << nodeName(mesh, v.node) << ", which has no such DOF");
      return L.row(v.node, v.component);
    };
    Teuchos::RCP<MultiVector> u1;
    if (!prestress.displacement.empty()) {
      // The structure solved the coupled static problem (theory §11.4): use
      // its u1 on this substructure's rows.
      CMS_INPUT_CHECK(static_cast<long long>(prestress.displacement.size()) != L.size,
                      model.name << ": prestress displacement has " << prestress.displacement.size()
                                 << " entries for " << L.size << " DOFs");
      u1 = Teuchos::rcp(new MultiVector(ownedMap, 1));
      auto uv = u1->getDataNonConst(0);
      for (std::size_t l = 0; l < ownedMap->getNodeNumElements(); ++l)
        uv[l] = prestress.displacement[ownedMap->getGlobalElement(static_cast<LocalOrdinal>(l))];
      out.u1 = u1;
    } else {
      std::vector<long long> heldRows;
      std::vector<PrestressConditions::NodalValue> heldDofs;
      for (const auto& h : prestress.held) {
        // A hold on a component the node does not carry is no constraint.
        if (h.node >= 0 && h.node < numNodes && !(L.present[h.node] & (1u << static_cast<int>(h.component))))
          continue;
        const long long r = rowOf(h, "hold");
        if (r < 0 || std::find(heldRows.begin(), heldRows.end(), r) != heldRows.end()) continue;
        heldRows.push_back(r);
        heldDofs.push_back(h);
      }
      auto f = Teuchos::rcp(new MultiVector(*out.f1, Teuchos::Copy));
      {
        auto fv = f->getDataNonConst(0);
        for (const auto& l : prestress.loads) {
          const long long r = rowOf(l, "load");
          const auto lid = ownedMap->getLocalElement(static_cast<GlobalOrdinal>(r));
          if (r >= 0 && lid != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) fv[lid] += l.value;
        }
      }
      Teuchos::RCP<const CrsMatrix> Ksolve = out.K;
      auto fSolve = Teuchos::rcp(new MultiVector(*f, Teuchos::Copy));
      if (!heldRows.empty()) {
        // Held rows and columns replaced by the identity, held loads zeroed:
        // u1 = 0 there, the rest is the supported problem.
        const std::vector<GlobalOrdinal> rows(heldRows.begin(), heldRows.end());
        Ksolve = holdDofsScaled(*out.K, rows);
        zeroHeldRows(*fSolve, rows);
      }
      SparseDirectSolver solver(Ksolve, "CHOLMOD");
      const auto outcome = solver.factor();
      if (outcome != SparseDirectSolver::Outcome::Factored)
        throw NumericalError(model.name + ": the centrifugal prestress needs a stiffness matrix that is "
                             "positive definite (a substructure restrained against rigid-body motion); "
                             "CHOLMOD: " + solver.failure() +
                             ". Add boundary conditions or set \"Stress Stiffening\" to false");
      u1 = Teuchos::rcp(new MultiVector(ownedMap, 1));
      solver.solve(*fSolve, *u1);
      out.u1 = u1;
      if (!heldRows.empty()) {
        MultiVector r(ownedMap, 1);
        out.K->apply(*u1, r);
        r.update(-1.0, *f, 1.0);
        auto rv = r.getData(0);
        std::vector<double> local(heldRows.size(), 0.0), global(heldRows.size(), 0.0);
        for (std::size_t i = 0; i < heldRows.size(); ++i) {
          const auto lid = ownedMap->getLocalElement(static_cast<GlobalOrdinal>(heldRows[i]));
          if (lid != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) local[i] = rv[lid];
        }
        Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
        for (std::size_t i = 0; i < heldDofs.size(); ++i) {
          out.reactions1.push_back(heldDofs[i]);
          out.reactions1.back().value = global[i];
        }
      }
    }
    MultiVector uOverlap(overlapMap, 1);
    uOverlap.doImport(*u1, Tpetra::Import<>(ownedMap, overlapMap), Tpetra::INSERT);
    auto u = uOverlap.getData(0);
    Target vKS = target("KS1");
    std::vector<double> ue(6 * 27);
    for (std::size_t local = 0; local < localItems.size() && failure.empty(); ++local) {
      const Item& it = items[localItems[local]];
      if (it.kind != Item::Kind::Frame && it.kind != Item::Kind::Solid) continue;
      const auto b = itemDofStart[local], e = itemDofStart[local + 1];
      for (auto p = b; p < e; ++p) ue[p - b] = itemLids[p] >= 0 ? u[itemLids[p]] : 0.0;
      try {
        if (it.kind == Item::Kind::Frame) {
          const FrameElement fe = frameOf(it);
          locate(local);
          // N(x) from the element's equilibrium under its own
          // centrifugal load: quadratic along it (theory §10).
          scatter(frameGeometricStiffness(fe, frameCentrifugalAxialForce(fe, ue.data(), spin)), vKS);
        } else {
          locate(local);
          scatter(solidGeometricStiffness(solidOf(it), ue.data()), vKS);
        }
      } catch (const std::exception& ex) {
        failureIsInput = dynamic_cast<const InputError*>(&ex) != nullptr;
        failure = model.name + ": element " + std::to_string(it.block->cellTags[it.cell]) + ": " + ex.what();
      }
    }
    throwIfAnyFailed(failure);
    out.KS1 = finish(vKS);
    out.prestressSeconds = secondsSince(t1);
  }
  return out;
}

}  // namespace cms::fem
