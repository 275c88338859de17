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
#include <exception>
#include <map>
#include <numeric>
#include <sstream>
#include <system_error>
#include <thread>
#include <unordered_map>
#include <utility>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/BlasThreads.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/fem/FrameElement.hpp"
#include "cms/fem/LumpedElements.hpp"
#include "cms/fem/SolidElement.hpp"

namespace cms::fem {

namespace {

/// The most nodes one item has: a Hex125 cell (cms/fem/SolidElement.hpp).
constexpr int kMaxItemNodes = 125;

constexpr std::uint8_t kTranslations = 0x07;
constexpr std::uint8_t kAllComponents = 0x3f;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// One contribution to the matrices: an element of a set, or a lumped item.
struct Item {
  enum class Kind : std::uint8_t { Frame, Solid, PointMass, GroundSpring, Spring, Hinge };
  Kind kind;
  int set;                 ///< index into the model's sets of that kind
  const mesh::CellBlock* block;  ///< Frame, Solid
  std::int64_t cell;       ///< Frame, Solid: cell index; lumped: first node
  std::int64_t other;      ///< Spring, Hinge: second node
};

/// One node pair of a hinge (theory §17): the second node b keeps only its
/// rotation about coordinate axis k (the one closest to the hinge axis n);
/// u_b = u_a and theta_b = theta_a + n phi with phi = (theta_b,k - theta_a,k) / n_k.
struct HingePair {
  std::int64_t a, b;
  int hinge;  ///< index into the model's hinges
  int k;      ///< the kept rotation of b: component 3 + k
  Vec3 n;     ///< unit axis
};

/// An item's element DOFs as combinations of rows, when it touches a
/// hinge's second node: element DOF i = sum_j T(i, j) row_j over the item's
/// row list (n x m, row-major). Element matrices A become T^T A T, loads
/// T^T f, and displacements T u.
struct ItemTransform {
  int n = 0, m = 0;
  std::vector<double> T;
};

std::string nodeName(const mesh::Mesh& mesh, std::int64_t node) {
  return "node " + std::to_string(mesh.nodeTags[node]);
}

/// Nodes of two node sets paired by coincident coordinates (a joint between
/// two coincident node sets; `what` names the item in messages, e.g.
/// "spring 'x'"); for springs (`anyPlace`) the single pair when both hold
/// one node, wherever they are.
std::vector<std::pair<std::int64_t, std::int64_t>> coincidentPairs(const mesh::Mesh& mesh, const std::string& what,
                                                                   const std::string& setA, const std::string& setB,
                                                                   bool anyPlace) {
  const auto a = mesh.nodeSet(setA), b = mesh.nodeSet(setB);
  std::vector<std::pair<std::int64_t, std::int64_t>> pairs;
  if (anyPlace && a.size() == 1 && b.size() == 1) return {{a[0], b[0]}};
  CMS_INPUT_CHECK(a.size() != b.size(),
                  what << ": node sets '" << setA << "' (" << a.size() << " nodes) and '" << setB << "' ("
                       << b.size() << " nodes) must have the same size to be paired");
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
    CMS_INPUT_CHECK(match < 0, what << ": " << nodeName(mesh, na) << " of set '" << setA
                                    << "' has no coincident node in set '" << setB << "' (within " << tol
                                    << " m)");
    pairs.emplace_back(na, match);
  }
  return pairs;
}

std::vector<std::pair<std::int64_t, std::int64_t>> springPairs(const mesh::Mesh& mesh, const SpringSet& s) {
  return coincidentPairs(mesh, "spring '" + s.name + "'", s.nodeSet, s.toNodeSet, true);
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
    case Item::Kind::Hinge: return 6;
    case Item::Kind::PointMass: {
      const auto& p = model.pointMasses[it.set];
      return std::any_of(p.inertia.begin(), p.inertia.end(), [](double v) { return v != 0.0; }) ? 6 : 3;
    }
    default: {  // springs and dampers (theory §13.1)
      const auto& s = model.springs[it.set];
      return hasRotationalStiffness(s.stiffness) || hasRotationalStiffness(s.damping) ? 6 : 3;
    }
  }
}

/// The item's element matrices (only those the model needs) in a fixed order.
struct ItemMatrices {
  ElementMatrix M, K;
  ElementMatrix D;    ///< viscous damping of a damper (empty otherwise)
  SpinMatrices spin;  ///< G1, KT1, f1 (empty when no spin)
  /// A stationary-frame rotor's material damping turning with it: the
  /// circulatory matrix per unit Omega of beta K (frames and hinges; empty
  /// otherwise, theory §13.1).
  ElementMatrix N1;
};

/// The assembly of one model, in the phases `run` calls in order. Each phase
/// leaves its results in members that the later phases read; none of them
/// communicates except where its comment says so (the maps, the ghost
/// pattern's export, the reduction of element failures, the final exports
/// and the prestress solve), so every rank calls them in the same order.
class Assembler {
 public:
  Assembler(const FiniteElementModel& model, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
            const PrestressConditions& prestress)
      : model_(model), mesh_(*model.mesh), comm_(comm), prestress_(prestress),
        numNodes_(static_cast<std::int64_t>(model.mesh->nodeCount())), rank_(comm->getRank()),
        nranks_(comm->getSize()) {}

  /// t0: when the assembly began (for the reported times).
  AssembledMatrices run(std::chrono::steady_clock::time_point t0) {
    listItems();
    layOutDofs();
    partitionNodes();
    mapItemRows();
    buildOverlapPattern();
    buildOwnedPattern();
    out_.setupSeconds = secondsSince(t0);
    out_.localItems = static_cast<long long>(localItems_.size());
    out_.ghostRows = static_cast<long long>(ghosts_.size());

    const auto tElements = std::chrono::steady_clock::now();
    assembleElements();
    out_.elementSeconds = secondsSince(tElements);

    const auto tExport = std::chrono::steady_clock::now();
    exportMatrices();
    out_.elementCount = static_cast<long long>(numElements_);
    out_.exportSeconds = secondsSince(tExport);
    out_.assemblySeconds = secondsSince(t0);

    CMS_INPUT_CHECK(!prestress_.empty() && !(rotatingFrame_ && model_.spin->stressStiffening),
                    model_.name << ": prestress conditions given, but the model has no rotating-frame "
                                   "spin with stress stiffening");
    if (rotatingFrame_ && model_.spin->stressStiffening) {
      const auto t1 = std::chrono::steady_clock::now();
      out_.u1 = prestressDisplacement();
      assembleGeometricStiffness(*out_.u1);
      out_.prestressSeconds = secondsSince(t1);
    }
    return std::move(out_);
  }

 private:
  using GO = GlobalOrdinal;
  using LO = LocalOrdinal;
  using Graph = Tpetra::CrsGraph<>;
  using Values = CrsMatrix::local_matrix_device_type::values_type;  // host memory (Serial node)
  /// One matrix's values on the shared pattern: the owned rows' final
  /// arrays and the ghost rows' small array.
  struct Target {
    Values owned, ghost;
  };

  // 1. Items, in set order: the same list on every rank (elements of every
  // element set, then point masses, grounded springs and node-pair springs).
  void listItems() {
    for (std::size_t s = 0; s < model_.elementSets.size(); ++s) {
      const auto& set = model_.elementSets[s];
      const auto kind = set.kind == ElementSet::Kind::Frame ? Item::Kind::Frame : Item::Kind::Solid;
      for (const mesh::CellBlock& b : mesh_.group(set.group).blocks)
        for (std::size_t c = 0; c < b.size(); ++c)
          items_.push_back({kind, static_cast<int>(s), &b, static_cast<std::int64_t>(c), -1});
    }
    numElements_ = items_.size();
    for (std::size_t s = 0; s < model_.pointMasses.size(); ++s)
      for (std::int64_t n : mesh_.nodeSet(model_.pointMasses[s].nodeSet))
        items_.push_back({Item::Kind::PointMass, static_cast<int>(s), nullptr, n, -1});
    for (std::size_t s = 0; s < model_.springs.size(); ++s) {
      const auto& sp = model_.springs[s];
      if (sp.toNodeSet.empty()) {
        for (std::int64_t n : mesh_.nodeSet(sp.nodeSet))
          items_.push_back({Item::Kind::GroundSpring, static_cast<int>(s), nullptr, n, -1});
      } else {
        for (auto [a, b] : springPairs(mesh_, sp))
          items_.push_back({Item::Kind::Spring, static_cast<int>(s), nullptr, a, b});
      }
    }
    // Hinges (theory §17): every pair is a constraint and an item (its
    // spring and damper, zero for a free hinge: the item puts the pair's
    // coupling in the pattern, which the prestress solve of a free hinge
    // uses).
    for (std::size_t h = 0; h < model_.hinges.size(); ++h) {
      const HingeSet& hs = model_.hinges[h];
      const Vec3 n = unit(hs.axis);
      int k = 0;
      for (int d = 1; d < 3; ++d)
        if (std::abs(n[d]) > std::abs(n[k])) k = d;
      for (auto [a, b] : coincidentPairs(mesh_, model_.name + ": hinge '" + hs.name + "'", hs.nodeSet,
                                         hs.toNodeSet, false)) {
        hingePairs_.push_back({a, b, static_cast<int>(h), k, n});
        items_.push_back({Item::Kind::Hinge, static_cast<int>(h), nullptr, a, b});
      }
    }
  }

  /// The item's nodes into out (at most kMaxItemNodes); returns their count.
  int itemNodes(const Item& it, std::int64_t* out) const {
    if (it.block) {
      const int n = it.block->nodesPerCell;
      std::copy_n(&it.block->nodes[it.cell * n], n, out);
      return n;
    }
    out[0] = it.cell;
    if (it.kind == Item::Kind::Spring || it.kind == Item::Kind::Hinge) { out[1] = it.other; return 2; }
    return 1;
  }

  // 2. Components per node (doc/architecture.md, "DOF layout"): elements
  // decide which components a node carries, lumped items may only add
  // translations (a rotation needs a frame node), every node must carry
  // something, fixed sets remove rows; rows are numbered in mesh order.
  void layOutDofs() {
    DofLayout& L = out_.layout;
    L.present.assign(numNodes_, 0);
    L.fixed.assign(numNodes_, 0);
    std::int64_t nodes[kMaxItemNodes];
    for (const Item& it : items_) {
      if (it.kind != Item::Kind::Frame && it.kind != Item::Kind::Solid) continue;
      const int nn = itemNodes(it, nodes);
      for (int a = 0; a < nn; ++a)
        L.present[nodes[a]] |= it.kind == Item::Kind::Frame ? kAllComponents : kTranslations;
    }
    for (const Item& it : items_) {
      if (it.kind == Item::Kind::Frame || it.kind == Item::Kind::Solid) continue;
      const int nn = itemNodes(it, nodes);
      const bool rotations = itemNodeDofs(it, model_) == 6;
      if (it.kind == Item::Kind::Hinge) continue;  // checked with every hinge pair below
      const std::string& name =
          it.kind == Item::Kind::PointMass ? model_.pointMasses[it.set].name : model_.springs[it.set].name;
      for (int a = 0; a < nn; ++a) {
        CMS_INPUT_CHECK(rotations && (L.present[nodes[a]] & kAllComponents) != kAllComponents,
                        model_.name << ": " << (it.kind == Item::Kind::PointMass ? "point mass '" : "spring '")
                                    << name << "' acts on the rotations of " << nodeName(mesh_, nodes[a])
                                    << ", which has none (only nodes of frame elements do)");
        L.present[nodes[a]] |= kTranslations;
      }
    }
    {
      std::vector<std::size_t> loose;
      for (std::int64_t n = 0; n < numNodes_; ++n)
        if (!L.present[n]) loose.push_back(mesh_.nodeTags[n]);
      if (!loose.empty()) {
        std::ostringstream os;
        os << mesh_.source << ": " << loose.size()
           << " node(s) belong to no element set or lumped item (unconnected), e.g. node";
        for (std::size_t i = 0; i < std::min<std::size_t>(loose.size(), 5); ++i) os << ' ' << loose[i];
        os << "; add their physical group to an element set or remove them from the mesh";
        throw InputError(os.str());
      }
    }
    for (const FixedSet& f : model_.fixed) {
      for (std::int64_t n : mesh_.nodeSet(f.nodeSet)) {
        if (f.all) { L.fixed[n] |= L.present[n]; continue; }
        for (Component c : f.components) {
          const std::uint8_t bit = 1u << static_cast<int>(c);
          CMS_INPUT_CHECK(!(L.present[n] & bit), "boundary condition '" << f.name << "' fixes "
                                                     << componentName(c) << " at " << nodeName(mesh_, n)
                                                     << ", which has no such DOF");
          L.fixed[n] |= bit;
        }
      }
    }
    layOutHinges();
    L.first.assign(numNodes_, 0);
    long long next = 0;
    for (std::int64_t n = 0; n < numNodes_; ++n) {
      L.first[n] = next;
      next += L.componentCount(n);
    }
    L.size = next;
    recordDependentDofs();
    CMS_INPUT_CHECK(L.size == 0, model_.name << ": every DOF is fixed; nothing to assemble");
  }

  // 2b. Hinges (theory §17): both nodes of a pair must be frame nodes (six
  // components); the second node's components other than its kept rotation
  // become slaved (no row). A node is the second node of at most one hinge
  // and never also a first node (no chains: the elimination is one level),
  // and carries no boundary condition (fix the first node instead).
  void layOutHinges() {
    DofLayout& L = out_.layout;
    if (hingePairs_.empty()) return;
    L.slaved.assign(numNodes_, 0);
    slaveOf_.assign(numNodes_, -1);
    std::vector<char> master(numNodes_, 0);
    for (const HingePair& p : hingePairs_) master[p.a] = 1;
    for (std::size_t i = 0; i < hingePairs_.size(); ++i) {
      const HingePair& p = hingePairs_[i];
      const HingeSet& h = model_.hinges[p.hinge];
      const std::string what = model_.name + ": hinge '" + h.name + "'";
      for (auto [node, set] : {std::pair{p.a, &h.nodeSet}, std::pair{p.b, &h.toNodeSet}})
        CMS_INPUT_CHECK((L.present[node] & kAllComponents) != kAllComponents,
                        what << ": " << nodeName(mesh_, node) << " of set '" << *set
                             << "' has no rotations (only nodes of frame elements do); a hinge joins frame nodes");
      CMS_INPUT_CHECK(p.a == p.b, what << ": " << nodeName(mesh_, p.a) << " is in both '" << h.nodeSet << "' and '"
                                       << h.toNodeSet << "'; a hinge needs two coincident nodes");
      CMS_INPUT_CHECK(slaveOf_[p.b] >= 0,
                      what << ": " << nodeName(mesh_, p.b) << " of set '" << h.toNodeSet
                           << "' is already the second node of hinge '"
                           << model_.hinges[hingePairs_[slaveOf_[p.b]].hinge].name << "'");
      CMS_INPUT_CHECK(master[p.b],
                      what << ": " << nodeName(mesh_, p.b) << " of set '" << h.toNodeSet
                           << "' is also the first node of a hinge; hinges in series need an element between them");
      CMS_INPUT_CHECK(L.fixed[p.b] != 0,
                      what << ": " << nodeName(mesh_, p.b) << " of set '" << h.toNodeSet
                           << "' has a boundary condition; fix the hinge's first node set '" << h.nodeSet
                           << "' instead (the second follows it)");
      slaveOf_[p.b] = static_cast<int>(i);
      L.slaved[p.b] = kAllComponents & ~static_cast<std::uint8_t>(1u << (3 + p.k));
    }
  }

  /// Every slaved DOF as its combination of rows (after the rows are numbered).
  void recordDependentDofs() {
    for (const HingePair& p : hingePairs_)
      for (int c = 0; c < 6; ++c) {
        if (c == 3 + p.k) continue;
        AssembledMatrices::DependentDof d;
        d.node = p.b;
        d.component = static_cast<Component>(c);
        expand(p.b, c, 1.0, d.terms);
        out_.dependent.push_back(std::move(d));
      }
  }

  /// Element DOF (node, c) as rows with coefficients (appended to out,
  /// scaled by w): the row itself, nothing for a fixed DOF, or for a
  /// hinge's slaved component its expression in the free rows (theory §17):
  /// u_b = u_a, theta_b,j = theta_a,j + (n_j / n_k)(theta_b,k - theta_a,k).
  void expand(std::int64_t node, int c, double w, std::vector<std::pair<long long, double>>& out) const {
    const DofLayout& L = out_.layout;
    if (L.slaved.empty() || !(L.slaved[node] & (1u << c))) {
      const long long r = L.row(node, static_cast<Component>(c));
      if (r >= 0 && w != 0.0) out.emplace_back(r, w);
      return;
    }
    const HingePair& p = hingePairs_[slaveOf_[node]];
    expand(p.a, c, w, out);
    if (c < 3) return;
    const double ratio = p.n[c - 3] / p.n[p.k];
    if (ratio == 0.0) return;
    expand(p.b, 3 + p.k, w * ratio, out);
    expand(p.a, 3 + p.k, -w * ratio, out);
  }

  // 3. Ownership: a coordinate-slab partition of the nodes (sorted along the
  // mesh's longest extent, cut into equal counts), whose rows each rank owns;
  // an item belongs to the rank owning its first node, so rows shared between
  // ranks occur only at the slab interfaces. Gmsh numbers boundary entities'
  // nodes first, so blocks of node numbers were not compact: 14% of the rows
  // were ghosts on 2 ranks (doc/benchmarks.md, "Assembly"). Rows keep the
  // mesh-order numbering, so matrices do not depend on the rank count.
  // Collective: the owned-row map.
  void partitionNodes() {
    const DofLayout& L = out_.layout;
    std::vector<int> owner(numNodes_, 0);
    if (nranks_ > 1) {
      int axis = 0;
      double extent[3];
      for (int c = 0; c < 3; ++c) {
        double lo = mesh_.x(0)[c], hi = lo;
        for (std::int64_t n = 1; n < numNodes_; ++n) {
          lo = std::min(lo, mesh_.x(n)[c]);
          hi = std::max(hi, mesh_.x(n)[c]);
        }
        extent[c] = hi - lo;
        if (extent[c] > extent[axis]) axis = c;
      }
      std::vector<std::int64_t> order(numNodes_);
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
        return mesh_.x(a)[axis] < mesh_.x(b)[axis];
      });
      for (std::int64_t k = 0; k < numNodes_; ++k) owner[order[k]] = static_cast<int>(k * nranks_ / numNodes_);
    }
    for (std::size_t i = 0; i < items_.size(); ++i) {
      const std::int64_t n0 = items_[i].block ? items_[i].block->nodes[items_[i].cell * items_[i].block->nodesPerCell]
                                              : items_[i].cell;
      if (owner[n0] == rank_) localItems_.push_back(i);
    }
    for (std::int64_t n = 0; n < numNodes_; ++n)
      if (owner[n] == rank_)
        for (int c = 0; c < L.componentCount(n); ++c) overlapGids_.push_back(static_cast<GO>(L.first[n] + c));
    numOwned_ = static_cast<LO>(overlapGids_.size());
    ownedMap_ = Teuchos::rcp(new Map(static_cast<GO>(L.size), Teuchos::ArrayView<const GO>(overlapGids_), 0, comm_));
  }

  // 4. Each local item's global rows (-1 for fixed), then the overlap map:
  // owned rows first, then the ghost rows in ascending order; and each item
  // row's local index in it. Collective: the overlap map.
  void mapItemRows() {
    const DofLayout& L = out_.layout;
    std::int64_t nodes[kMaxItemNodes];
    itemDofStart_.assign(localItems_.size() + 1, 0);
    std::vector<std::pair<long long, double>> terms;
    for (std::size_t k = 0; k < localItems_.size(); ++k) {
      const Item& it = items_[localItems_[k]];
      const int nn = itemNodes(it, nodes), nd = itemNodeDofs(it, model_);
      bool hinged = false;
      for (int a = 0; a < nn && !slaveOf_.empty(); ++a) hinged = hinged || slaveOf_[nodes[a]] >= 0;
      if (!hinged) {
        for (int a = 0; a < nn; ++a)
          for (int c = 0; c < nd; ++c) itemDofs_.push_back(L.row(nodes[a], static_cast<Component>(c)));
      } else {
        // The item's rows: every row its element DOFs depend on, and T.
        std::vector<std::vector<std::pair<long long, double>>> dofTerms;
        std::vector<long long> rows;
        for (int a = 0; a < nn; ++a)
          for (int c = 0; c < nd; ++c) {
            terms.clear();
            expand(nodes[a], c, 1.0, terms);
            for (const auto& t : terms) rows.push_back(t.first);
            dofTerms.push_back(terms);
          }
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        ItemTransform& tr = transforms_[k];
        tr.n = nn * nd;
        tr.m = static_cast<int>(rows.size());
        tr.T.assign(static_cast<std::size_t>(tr.n) * tr.m, 0.0);
        for (int i = 0; i < tr.n; ++i)
          for (const auto& [r, w] : dofTerms[i])
            tr.T[static_cast<std::size_t>(i) * tr.m + (std::lower_bound(rows.begin(), rows.end(), r) - rows.begin())] += w;
        itemDofs_.insert(itemDofs_.end(), rows.begin(), rows.end());
      }
      itemDofStart_[k + 1] = static_cast<std::int64_t>(itemDofs_.size());
    }
    rowLid_.assign(L.size, -1);  // global row -> overlap lid (one int per row: 4 MB at 10^6)
    for (LO l = 0; l < numOwned_; ++l) rowLid_[overlapGids_[l]] = l;
    for (long long g : itemDofs_)
      if (g >= 0 && rowLid_[g] < 0) ghosts_.push_back(g);
    std::sort(ghosts_.begin(), ghosts_.end());
    ghosts_.erase(std::unique(ghosts_.begin(), ghosts_.end()), ghosts_.end());
    numOverlap_ = numOwned_ + static_cast<LO>(ghosts_.size());
    for (std::size_t k = 0; k < ghosts_.size(); ++k) {
      rowLid_[ghosts_[k]] = numOwned_ + static_cast<LO>(k);
      overlapGids_.push_back(static_cast<GO>(ghosts_[k]));
    }
    overlapMap_ = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                       Teuchos::ArrayView<const GO>(overlapGids_), 0, comm_));
    itemLids_.resize(itemDofs_.size());
    std::transform(itemDofs_.begin(), itemDofs_.end(), itemLids_.begin(),
                   [&](long long g) { return g < 0 ? LO(-1) : rowLid_[g]; });
  }

  // 5. The shared CSR pattern over the overlap rows (columns: overlap lids):
  // every pair of an item's free rows, counted, filled, then each row sorted
  // and deduplicated in place, compacting the arrays. The count is of the
  // item's free rows only: counting its fixed DOFs too left unfilled slots,
  // which read as column lid 0 and were stored as zero entries coupling
  // every row next to a support to the rank's first column (the rotor hub's
  // K held 999 of them on one rank; on two ranks other ones, so the stored
  // pattern depended on the rank count).
  void buildOverlapPattern() {
    rowPtr_ = Teuchos::ArrayRCP<std::size_t>(numOverlap_ + 1, 0);
    for (std::size_t i = 0; i + 1 < itemDofStart_.size(); ++i) {
      const auto b = itemDofStart_[i], e = itemDofStart_[i + 1];
      const auto free = static_cast<std::size_t>(
          std::count_if(itemLids_.begin() + b, itemLids_.begin() + e, [](LO l) { return l >= 0; }));
      for (auto p = b; p < e; ++p)
        if (itemLids_[p] >= 0) rowPtr_[itemLids_[p] + 1] += free;
    }
    for (LO r = 0; r < numOverlap_; ++r) rowPtr_[r + 1] += rowPtr_[r];
    cols_.assign(rowPtr_[numOverlap_], 0);
    {
      std::vector<std::size_t> fill(rowPtr_.begin(), rowPtr_.end() - 1);
      for (std::size_t i = 0; i + 1 < itemDofStart_.size(); ++i) {
        const auto b = itemDofStart_[i], e = itemDofStart_[i + 1];
        for (auto p = b; p < e; ++p) {
          if (itemLids_[p] < 0) continue;
          for (auto q = b; q < e; ++q)
            if (itemLids_[q] >= 0) cols_[fill[itemLids_[p]]++] = itemLids_[q];
        }
      }
    }
    std::size_t write = 0;
    for (LO r = 0; r < numOverlap_; ++r) {
      const std::size_t b = rowPtr_[r], e = rowPtr_[r + 1];
      std::sort(cols_.begin() + b, cols_.begin() + e);
      const std::size_t start = write;
      for (std::size_t p = b; p < e; ++p)
        if (p == b || cols_[p] != cols_[p - 1]) cols_[write++] = cols_[p];
      rowPtr_[r] = start;
    }
    rowPtr_[numOverlap_] = write;
    cols_.resize(write);
    cols_.shrink_to_fit();
  }

  // 6. The owned pattern, before any value is computed. Only the ghost rows
  // (a slab interface) cross ranks: their pattern is exported once and
  // merged into the owned rows' own pattern locally; element values are then
  // scattered straight into the owned rows' final arrays and a small ghost
  // array, which an Export (ADD) sends to the owners. Exporting every matrix
  // whole with Tpetra's exportAndFillComplete, or even just the whole
  // pattern, cost more than the element loop at 10^6 DOFs
  // (doc/benchmarks.md, "Assembly"). Collective: the exporters, the ghost
  // pattern's export, the column map and the graphs' fill.
  void buildOwnedPattern() {
    exporter_ = Teuchos::rcp(new Tpetra::Export<>(overlapMap_, ownedMap_));
    ghostMap_ = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                     Teuchos::ArrayView<const GO>(ghosts_.empty() ? nullptr : overlapGids_.data() + numOwned_,
                                                                  ghosts_.size()),
                                     0, comm_));
    ghostBegin_ = rowPtr_[numOwned_];
    {
      Teuchos::ArrayRCP<std::size_t> ghostRowPtr(ghosts_.size() + 1);
      for (std::size_t r = 0; r <= ghosts_.size(); ++r) ghostRowPtr[r] = rowPtr_[numOwned_ + r] - ghostBegin_;
      Teuchos::ArrayRCP<LO> ghostCols(cols_.size() - ghostBegin_);
      std::copy(cols_.begin() + ghostBegin_, cols_.end(), ghostCols.begin());
      auto g = Teuchos::rcp(new Graph(ghostMap_, overlapMap_, ghostRowPtr, ghostCols));
      g->expertStaticFillComplete(ownedMap_, ownedMap_);
      ghostGraph_ = g;
    }
    ghostExporter_ = Teuchos::rcp(new Tpetra::Export<>(ghostMap_, ownedMap_));
    // The owned pattern: columns numbered as in the overlap map (so an owned
    // row's own entries keep their column lids), then the columns only other
    // ranks' elements bring, appended.
    Teuchos::ArrayRCP<std::size_t> ownedRowPtr(numOwned_ + 1, 0);
    std::vector<LO> ownedCols;
    std::vector<GO> colGids(overlapGids_);
    {
      const auto received = Tpetra::exportAndFillCompleteCrsGraph<Graph>(ghostGraph_, *ghostExporter_, ownedMap_, ownedMap_);
      const auto rec = received->getLocalGraphHost();
      const auto& recCols = *received->getColMap();
      std::unordered_map<GO, LO> extra;
      ownedCols.reserve(ghostBegin_ + rec.entries.extent(0));
      for (LO r = 0; r < numOwned_; ++r) {
        const std::size_t start = ownedCols.size();
        ownedCols.insert(ownedCols.end(), cols_.begin() + rowPtr_[r], cols_.begin() + rowPtr_[r + 1]);
        const std::size_t rb = rec.row_map(r), re = rec.row_map(r + 1);
        for (std::size_t p = rb; p < re; ++p) {
          const GO g = recCols.getGlobalElement(rec.entries(p));
          LO l = g < static_cast<GO>(rowLid_.size()) ? rowLid_[g] : -1;
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
    std::vector<LO>().swap(rowLid_);
    auto colMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                       Teuchos::ArrayView<const GO>(colGids), 0, comm_));
    ownedNnz_ = ownedCols.size();
    {
      Teuchos::ArrayRCP<LO> c(ownedNnz_);
      std::copy(ownedCols.begin(), ownedCols.end(), c.begin());
      std::vector<LO>().swap(ownedCols);
      auto g = Teuchos::rcp(new Graph(ownedMap_, colMap, ownedRowPtr, c));
      g->expertStaticFillComplete(ownedMap_, ownedMap_);
      ownedGraph_ = g;
    }
    ownedLocal_ = ownedGraph_->getLocalGraphHost();
  }

  /// Where an item's entries go (locate()): p >= 0, entry p of the owned
  /// arrays; p <= -2, entry -p-2 of the ghost arrays; -1, a fixed DOF. And
  /// the offsets locate() keeps from row to row.
  struct Places {
    std::vector<std::int64_t> positions, offsets;
  };
  /// Positions of a local item's entries: found once per item and reused by
  /// every matrix of that item. p >= 0: entry p of the owned arrays; p <= -2:
  /// entry -p-2 of the ghost arrays; -1: fixed DOF. A row's columns are
  /// sorted and distinct, so an offset that holds the column is its place:
  /// each column's offset in the previous row (the rows of one node share
  /// their layout), then the place after the previous column (a node's
  /// columns are consecutive), are tried with one comparison each before a
  /// binary search. The searches alone, one per entry, took two fifths of
  /// the element phase of the rotor's hub (doc/benchmarks.md, "Assembly: the
  /// entries' places").
  void locate(std::size_t local, Places& at) const {
    const auto& owned = ownedLocal_;
    const auto b = itemDofStart_[local], e = itemDofStart_[local + 1];
    const int n = static_cast<int>(e - b);
    std::vector<std::int64_t>& positions = at.positions;
    std::vector<std::int64_t>& offsets = at.offsets;
    positions.assign(static_cast<std::size_t>(n) * n, -1);
    offsets.assign(static_cast<std::size_t>(n), -1);
    for (int i = 0; i < n; ++i) {
      const LO r = itemLids_[b + i];
      if (r < 0) continue;
      const bool mine = r < numOwned_;
      const LO* base = mine ? owned.entries.data() : cols_.data();
      const LO* rb = base + (mine ? owned.row_map(r) : rowPtr_[r]);
      const LO* re = base + (mine ? owned.row_map(r + 1) : rowPtr_[r + 1]);
      const std::int64_t length = re - rb;
      auto holds = [&](std::int64_t off, LO c) { return off >= 0 && off < length && rb[off] == c; };
      std::int64_t previous = -1;
      for (int j = 0; j < n; ++j) {
        const LO c = itemLids_[b + j];
        if (c < 0) continue;
        std::int64_t off = offsets[j];
        if (!holds(off, c)) off = previous + 1;
        if (!holds(off, c)) off = std::lower_bound(rb, re, c) - rb;
        offsets[j] = previous = off;
        const std::int64_t p = (rb - base) + off;
        positions[static_cast<std::size_t>(i) * n + j] =
            mine ? p : -2 - (p - static_cast<std::int64_t>(ghostBegin_));
      }
    }
  }
  Target target(const char* name) const {
    return Target{Values(std::string(name) + " owned", ownedNnz_),
                  Values(std::string(name) + " ghost", cols_.size() - ghostBegin_)};
  }
  /// Adds `count` element matrices at the positions locate() found, in one
  /// pass over them (the positions read once).
  void scatter(const ElementMatrix* const* from, const Places& at, Target* const* to, int count) const {
    double* owned[5];
    double* ghost[5];
    const double* a[5];
    for (int q = 0; q < count; ++q) owned[q] = to[q]->owned.data(), ghost[q] = to[q]->ghost.data(), a[q] = from[q]->a.data();
    const std::size_t nn = at.positions.size();
    for (std::size_t k = 0; k < nn; ++k) {
      const std::int64_t p = at.positions[k];
      if (p >= 0) {
        for (int q = 0; q < count; ++q) owned[q][p] += a[q][k];
      } else if (p <= -2) {
        for (int q = 0; q < count; ++q) ghost[q][-2 - p] += a[q][k];
      }
    }
  }
  void scatterVector(std::size_t local, const std::vector<double>& f, std::vector<double>& v) const {
    const auto b = itemDofStart_[local], e = itemDofStart_[local + 1];
    for (auto p = b; p < e; ++p)
      if (itemLids_[p] >= 0) v[itemLids_[p]] += f[p - b];
  }

  FrameElement frameOf(const Item& it) const {
    const auto& set = model_.elementSets[it.set];
    FrameElement fe;
    const std::int64_t* cn = &it.block->nodes[it.cell * it.block->nodesPerCell];
    std::copy_n(mesh_.x(cn[0]), 3, fe.x1.begin());
    std::copy_n(mesh_.x(cn[1]), 3, fe.x2.begin());
    fe.material = model_.materials.at(set.material);
    fe.section = set.section;
    fe.theory = set.theory;
    return fe;
  }
  /// The solid element of an item, its node coordinates copied into `xyz`
  /// (the caller's: items are made on several threads).
  SolidElement solidOf(const Item& it, std::vector<double>& xyz) const {
    const auto& set = model_.elementSets[it.set];
    const std::int64_t* cn = &it.block->nodes[it.cell * it.block->nodesPerCell];
    xyz.resize(3 * static_cast<std::size_t>(it.block->nodesPerCell));
    for (int a = 0; a < it.block->nodesPerCell; ++a) std::copy_n(mesh_.x(cn[a]), 3, &xyz[3 * a]);
    return SolidElement{solidTypeOf(set, *it.block), xyz.data(), model_.materials.at(set.material)};
  }
  PointMass pointMassOf(const Item& it) const {
    PointMass p;
    p.m = model_.pointMasses[it.set].mass;
    p.inertia = model_.pointMasses[it.set].inertia;
    std::copy_n(mesh_.x(it.cell), 3, p.x.begin());
    return p;
  }

  /// The item's element matrices: K and M, and the spin terms the model's
  /// frame needs (rotating: G1, KT1, f1; stationary: G1, and the tilt
  /// stiffness in KT1 when the frame itself turns).
  /// `xyz`: scratch for a solid's coordinates (solidOf).
  ItemMatrices itemMatrices(const Item& it, std::vector<double>& xyz) const {
    const int nd = itemNodeDofs(it, model_);
    const Spin spin = spinning_ ? model_.spin->spin : Spin{};
    ItemMatrices m;
    switch (it.kind) {
      case Item::Kind::Frame: {
        const FrameElement fe = frameOf(it);
        m.K = frameStiffness(fe);
        m.M = frameMass(fe);
        if (rotatingFrame_) m.spin = frameSpinMatrices(fe, spin);
        else if (spinning_) m.spin.G1 = frameStationaryGyroscopic(fe, spin.axis);
        if (tilt_) m.spin.KT1 = frameStationaryTiltStiffness(fe, spin.axis, *model_.spin->frameAxis);
        break;
      }
      case Item::Kind::Solid: {
        const SolidElement se = solidOf(it, xyz);
        m.K = solidStiffness(se);
        m.M = rotatingFrame_ ? solidMassWithSpin(se, spin, m.spin) : solidMass(se);
        break;
      }
      case Item::Kind::PointMass: {
        const PointMass p = pointMassOf(it);
        m.M = pointMassMatrix(p, nd);
        m.K = ElementMatrix(nd);
        if (rotatingFrame_) m.spin = pointMassSpinMatrices(p, spin, nd);
        else if (spinning_ && nd == 6) m.spin.G1 = pointMassStationaryGyroscopic(p, spin.axis);
        if (tilt_ && nd == 6) m.spin.KT1 = pointMassStationaryTiltStiffness(p, spin.axis, *model_.spin->frameAxis);
        break;
      }
      case Item::Kind::GroundSpring:
        // (Springs and dampers are the rotor's bearings and supports: they
        // do not turn with it, so they add no circulatory term.)
        // A viscous damper's matrix has the spring's form with c for k.
        m.K = groundedSpringMatrix(model_.springs[it.set].stiffness, nd);
        if (damped_) m.D = groundedSpringMatrix(model_.springs[it.set].damping, nd);
        break;
      case Item::Kind::Spring:
        m.K = twoNodeSpringMatrix(model_.springs[it.set].stiffness, nd);
        if (damped_) m.D = twoNodeSpringMatrix(model_.springs[it.set].damping, nd);
        break;
      case Item::Kind::Hinge: {
        // A spring k and a damper c on the relative rotation about the axis,
        // phi = n . (theta_b - theta_a): k w w^T, c w w^T (theory §17).
        const HingeSet& h = model_.hinges[it.set];
        const Vec3 n = unit(h.axis);
        double w[12] = {};
        for (int d = 0; d < 3; ++d) w[3 + d] = -n[d], w[9 + d] = n[d];
        m.K = ElementMatrix(12);
        if (damped_) m.D = ElementMatrix(12);
        for (int i = 0; i < 12; ++i)
          for (int j = 0; j < 12; ++j) {
            m.K(i, j) = h.stiffness * w[i] * w[j];
            if (damped_) m.D(i, j) = h.damping * w[i] * w[j];
          }
        break;
      }
    }
    // The rotor's material damping, beta K of what turns with it (its
    // frames and hinges; not its springs, which are its bearings and
    // supports), resists the strain rate seen by the material: in the
    // stationary frame it adds the circulatory -Omega beta K A (theory
    // §13.1). The substructure applies beta K_R as damping; alpha M damps
    // absolute velocity and stays stationary.
    if (circulatory_ && (it.kind == Item::Kind::Frame || it.kind == Item::Kind::Hinge)) {
      ElementMatrix Dr(m.K.n);
      for (std::size_t q = 0; q < Dr.a.size(); ++q) Dr.a[q] = model_.damping.beta * m.K.a[q];
      m.N1 = stationaryRotatingDamping(Dr, spin.axis, nd);
    }
    return m;
  }

  /// Adds local item's matrix A at the positions locate() found: A itself,
  /// or T^T A T for an item at a hinge's second node (no copy of A for the
  /// others: most items).
  void scatterItem(std::size_t local, const ElementMatrix& A, const Places& at, Target& t) const {
    Target* to[1] = {&t};
    if (transforms_.empty() || !transforms_.count(local)) {
      const ElementMatrix* from[1] = {&A};
      scatter(from, at, to, 1);
    } else {
      const ElementMatrix hinged = constrained(local, A);
      const ElementMatrix* from[1] = {&hinged};
      scatter(from, at, to, 1);
    }
  }
  /// T^T A T for an item with a transform (theory §17).
  ElementMatrix constrained(std::size_t local, const ElementMatrix& A) const {
    const auto t = transforms_.find(local);
    if (t == transforms_.end() || A.n == 0) return A;
    const ItemTransform& tr = t->second;
    ElementMatrix out(tr.m);
    std::vector<double> at(static_cast<std::size_t>(tr.n) * tr.m, 0.0);  // A T, n x m
    for (int i = 0; i < tr.n; ++i)
      for (int l = 0; l < tr.n; ++l) {
        const double a = A(i, l);
        if (a == 0.0) continue;
        for (int j = 0; j < tr.m; ++j) at[static_cast<std::size_t>(i) * tr.m + j] += a * tr.T[static_cast<std::size_t>(l) * tr.m + j];
      }
    for (int i = 0; i < tr.n; ++i)
      for (int p = 0; p < tr.m; ++p) {
        const double t_ip = tr.T[static_cast<std::size_t>(i) * tr.m + p];
        if (t_ip == 0.0) continue;
        for (int j = 0; j < tr.m; ++j) out(p, j) += t_ip * at[static_cast<std::size_t>(i) * tr.m + j];
      }
    return out;
  }
  /// T^T f for an item with a transform.
  std::vector<double> constrained(std::size_t local, const std::vector<double>& f) const {
    const auto t = transforms_.find(local);
    if (t == transforms_.end() || f.empty()) return f;
    const ItemTransform& tr = t->second;
    std::vector<double> out(tr.m, 0.0);
    for (int i = 0; i < tr.n; ++i)
      for (int p = 0; p < tr.m; ++p) out[p] += tr.T[static_cast<std::size_t>(i) * tr.m + p] * f[i];
    return out;
  }

  /// One local item's matrices and places, made on any thread.
  struct Made {
    ItemMatrices m;
    Places at;
    std::vector<double> rows, dofs, xyz;  ///< the maker's own scratch (KS1: u at its rows and DOFs)
    bool skip = false;         ///< nothing to add for this item
    std::exception_ptr error;
  };

  /// The local items in order. `make` (the item's matrices, into a Made)
  /// and locate() run on this rank's threads (its share of the node's
  /// cores: blasThreads(), one under OPENBLAS_NUM_THREADS=1 or two ranks on
  /// two cores), a chunk of items at a time; `add` then scatters the chunk
  /// on this thread, item after item, so every entry is the same sum in the
  /// same order as on one thread. The first item whose make or add throws
  /// goes to `fail` and the loop ends there, as the one-thread loop did.
  /// Element matrices and their places were three fifths of the element
  /// phase, their scatter the rest (doc/benchmarks.md, "Assembly: the
  /// entries' places").
  template <class Make, class Add, class Fail>
  void forLocalItems(Make make, Add add, Fail fail) {
    constexpr double kChunkBytes = 8.0 * (1 << 20);
    const std::size_t count = localItems_.size();
    const std::size_t threads = static_cast<std::size_t>(std::max(1, blasThreads()));
    std::vector<Made> made;
    for (std::size_t first = 0; first < count && failure_.empty();) {
      // At least an item per thread, at most ~kChunkBytes of matrices and places.
      std::size_t last = first;
      for (double bytes = 0.0; last < count && (last - first < threads || bytes < kChunkBytes); ++last) {
        const double n = static_cast<double>(itemDofStart_[last + 1] - itemDofStart_[last]);
        bytes += 6.0 * 8.0 * n * n;
      }
      if (made.size() < last - first) made.resize(last - first);
      const std::size_t parts = std::min(threads, last - first);
      auto work = [&](std::size_t part) {
        const std::size_t size = last - first;
        for (std::size_t k = first + size * part / parts; k < first + size * (part + 1) / parts; ++k) {
          Made& d = made[k - first];
          d.skip = false;
          d.error = nullptr;
          try {
            make(k, d);
            if (!d.skip) locate(k, d.at);
          } catch (...) {
            d.error = std::current_exception();
          }
        }
      };
      std::vector<std::thread> pool;
      for (std::size_t t = 1; t < parts; ++t) {
        try {
          pool.emplace_back(work, t);
        } catch (const std::system_error&) {  // no thread to be had: its part here
          work(t);
        }
      }
      work(0);
      for (auto& th : pool) th.join();
      for (std::size_t k = first; k < last; ++k) {
        const Made& d = made[k - first];
        try {
          if (d.error) std::rethrow_exception(d.error);
          if (!d.skip) add(k, d);
        } catch (const std::exception& e) {
          fail(k, e);
          break;
        }
      }
      first = last;
    }
  }

  // 7. Element matrices into the owned and ghost arrays. Errors are collected
  // and reduced so every rank throws together (a rank's own elements may be
  // the only bad ones). Collective: that reduction.
  void assembleElements() {
    spinning_ = model_.spin.has_value();
    rotatingFrame_ = spinning_ && model_.spin->frame == SpinDefinition::Frame::Rotating;
    damped_ = std::any_of(model_.springs.begin(), model_.springs.end(), [](const SpringSet& s) {
      return std::any_of(s.damping.begin(), s.damping.end(), [](double c) { return c != 0.0; });
    }) || std::any_of(model_.hinges.begin(), model_.hinges.end(), [](const HingeSet& h) { return h.damping != 0.0; });
    if (damped_) vD_ = target("D");
    tilt_ = spinning_ && !rotatingFrame_ && model_.spin->frameAxis.has_value();
    circulatory_ = spinning_ && !rotatingFrame_ && model_.damping.beta != 0.0;
    if (circulatory_) vN_ = target("N1"), vKR_ = target("KR");
    vM_ = target("M");
    vK_ = target("K");
    if (spinning_) vG_ = target("G1");
    if (rotatingFrame_) { vKT_ = target("KT1"); vf_.assign(numOverlap_, 0.0); }
    if (tilt_) vKT_ = target("KX1");

    forLocalItems(
        [&](std::size_t local, Made& made) { made.m = itemMatrices(items_[localItems_[local]], made.xyz); },
        [&](std::size_t local, const Made& made) {
          const ItemMatrices& m = made.m;
          // Every matrix in one pass over the places (the item's place in
          // each target is the same); T^T A T for an item at a hinge's
          // second node.
          const ElementMatrix* from[7];
          Target* to[7];
          int count = 0;
          auto put = [&](const ElementMatrix& A, Target& t) { from[count] = &A, to[count++] = &t; };
          put(m.K, vK_);
          if (m.M.n) put(m.M, vM_);
          if (m.D.n) put(m.D, vD_);
          if (m.spin.G1.n) put(m.spin.G1, vG_);
          if ((rotatingFrame_ || tilt_) && m.spin.KT1.n) put(m.spin.KT1, vKT_);
          if (m.N1.n) put(m.N1, vN_), put(m.K, vKR_);  // (N1: an item that turns with the rotor)
          ElementMatrix hinged[7];
          if (!transforms_.empty() && transforms_.count(local))
            for (int q = 0; q < count; ++q) hinged[q] = constrained(local, *from[q]), from[q] = &hinged[q];
          scatter(from, made.at, to, count);
          if (rotatingFrame_ && !m.spin.f1.empty()) {
            if (transforms_.count(local)) scatterVector(local, constrained(local, m.spin.f1), vf_);
            else scatterVector(local, m.spin.f1, vf_);
          }
        },
        [&](std::size_t local, const std::exception& e) {
          const Item& it = items_[localItems_[local]];
          std::ostringstream os;
          os << model_.name << ": ";
          if (it.block) os << "element " << it.block->cellTags[it.cell] << " of set '"
                           << model_.elementSets[it.set].group << "'";
          else os << nodeName(mesh_, it.cell);
          os << ": " << e.what();
          failure_ = os.str();
          failureIsInput_ = dynamic_cast<const InputError*>(&e) != nullptr;
        });
    throwIfAnyFailed();
  }

  /// Collective: throws on every rank the message of the lowest rank whose
  /// elements failed (InputError if any failure was one, else NumericalError).
  void throwIfAnyFailed() const {
    int bad = failure_.empty() ? 0 : (failureIsInput_ ? 2 : 1), anyBad = 0;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, bad, Teuchos::outArg(anyBad));
    if (!anyBad) return;
    int src = bad ? rank_ : nranks_, lowest = 0;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, src, Teuchos::outArg(lowest));
    int len = static_cast<int>(failure_.size());
    Teuchos::broadcast(*comm_, lowest, Teuchos::outArg(len));
    std::string msg = failure_;
    msg.resize(len);
    Teuchos::broadcast(*comm_, lowest, len, msg.data());
    if (anyBad == 2) throw InputError(msg);
    throw NumericalError(msg);
  }

  /// Collective: the owned matrix of one target, its ghost rows added by
  /// the Export (ADD); the target's arrays are released.
  Teuchos::RCP<const CrsMatrix> finish(Target& t) const {
    CrsMatrix ghost(ghostGraph_, t.ghost);
    if (!ghost.isFillComplete()) ghost.fillComplete(ownedMap_, ownedMap_);
    auto A = Teuchos::rcp(new CrsMatrix(ownedGraph_, t.owned));
    t = Target();
    A->resumeFill();
    A->doExport(ghost, *ghostExporter_, Tpetra::ADD);
    A->fillComplete(ownedMap_, ownedMap_);
    return A;
  }

  // 8. The ghost rows sent to their owners: the finished M, K and spin
  // matrices and the centrifugal load f1. Collective.
  void exportMatrices() {
    out_.map = ownedMap_;
    out_.M = finish(vM_);
    out_.K = finish(vK_);
    if (damped_) out_.D = finish(vD_);
    if (spinning_) out_.G1 = finish(vG_);
    if (circulatory_) out_.N1 = finish(vN_), out_.KR = finish(vKR_);
    if (tilt_) out_.KX1 = finish(vKT_);
    if (rotatingFrame_) {
      out_.KT1 = finish(vKT_);
      MultiVector fOverlap(overlapMap_, 1);
      {
        auto view = fOverlap.getDataNonConst(0);
        std::copy(vf_.begin(), vf_.end(), view.begin());
      }
      auto f1 = Teuchos::rcp(new MultiVector(ownedMap_, 1));
      f1->doExport(fOverlap, *exporter_, Tpetra::ADD);
      out_.f1 = f1;
    }
  }

  /// The rows of a held or loaded DOF of the PrestressConditions with their
  /// coefficients: one row, none if the model fixes it, or for a hinge's
  /// slaved DOF its expression in the free rows (theory §17); an InputError
  /// if the node or component does not exist.
  std::vector<std::pair<long long, double>> prestressRows(const PrestressConditions::NodalValue& v,
                                                          const char* what) const {
    const DofLayout& L = out_.layout;
    CMS_INPUT_CHECK(v.node < 0 || v.node >= numNodes_,
                    model_.name << ": prestress " << what << " at node index " << v.node << " (mesh has "
                                << numNodes_ << " nodes)");
    CMS_INPUT_CHECK(!(L.present[v.node] & (1u << static_cast<int>(v.component))),
                    model_.name << ": prestress " << what << " on " << componentName(v.component) << " at "
                                << nodeName(mesh_, v.node) << ", which has no such DOF");
    std::vector<std::pair<long long, double>> rows;
    expand(v.node, static_cast<int>(v.component), 1.0, rows);
    return rows;
  }

  // 9a. Centrifugal prestress (theory §10): u1 per unit Omega^2, either the
  // structure's own (it solved the coupled static problem, theory §11.4) or
  // this substructure's K u1 = f1 + loads with the held DOFs held (§10.2),
  // whose reactions are recorded. Collective: the solve and the reactions.
  Teuchos::RCP<const MultiVector> prestressDisplacement() {
    const DofLayout& L = out_.layout;
    if (!prestress_.displacement.empty()) {
      CMS_INPUT_CHECK(static_cast<long long>(prestress_.displacement.size()) != L.size,
                      model_.name << ": prestress displacement has " << prestress_.displacement.size()
                                  << " entries for " << L.size << " DOFs");
      auto u1 = Teuchos::rcp(new MultiVector(ownedMap_, 1));
      auto uv = u1->getDataNonConst(0);
      for (std::size_t l = 0; l < ownedMap_->getNodeNumElements(); ++l)
        uv[l] = prestress_.displacement[ownedMap_->getGlobalElement(static_cast<LocalOrdinal>(l))];
      return u1;
    }
    // Held DOFs and children's loads: rows resolved here, where the layout
    // is known. A held DOF the model already fixes has no row and needs no
    // hold; a hold on a component the node does not carry is no constraint.
    std::vector<long long> heldRows;
    std::vector<PrestressConditions::NodalValue> heldDofs;
    for (const auto& h : prestress_.held) {
      if (h.node >= 0 && h.node < numNodes_ && !(L.present[h.node] & (1u << static_cast<int>(h.component))))
        continue;
      const auto rows = prestressRows(h, "hold");
      if (rows.empty()) continue;
      // A hinge's slaved translation is its first node's: hold that. A
      // slaved rotation mixing rows is a constraint holdDofs cannot make.
      CMS_INPUT_CHECK(rows.size() != 1 || rows[0].second != 1.0,
                      model_.name << ": prestress hold on " << componentName(h.component) << " at "
                                  << nodeName(mesh_, h.node) << ", the second node of hinge '"
                                  << model_.hinges[hingePairs_[slaveOf_[h.node]].hinge].name
                                  << "', which follows the hinge rotation; attach at the hinge's first node set");
      const long long r = rows[0].first;
      if (std::find(heldRows.begin(), heldRows.end(), r) != heldRows.end()) continue;
      heldRows.push_back(r);
      heldDofs.push_back(h);
    }
    auto f = Teuchos::rcp(new MultiVector(*out_.f1, Teuchos::Copy));
    {
      auto fv = f->getDataNonConst(0);
      for (const auto& l : prestress_.loads)
        for (const auto& [r, w] : prestressRows(l, "load")) {  // T^T f for a hinge's slaved DOF
          const auto lid = ownedMap_->getLocalElement(static_cast<GlobalOrdinal>(r));
          if (lid != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) fv[lid] += w * l.value;
        }
    }
    Teuchos::RCP<const CrsMatrix> Ksolve = holdFreeHinges();
    const bool plainK = Ksolve.get() == out_.K.get();
    auto fSolve = Teuchos::rcp(new MultiVector(*f, Teuchos::Copy));
    std::vector<GlobalOrdinal> rows(heldRows.begin(), heldRows.end());
    if (!heldRows.empty()) {
      // Held rows and columns replaced by the identity, held loads zeroed:
      // u1 = 0 there, the rest is the supported problem.
      Ksolve = holdDofsScaled(*Ksolve, rows);
      zeroHeldRows(*fSolve, rows);
    }
    auto solver = std::make_shared<SparseDirectSolver>(Ksolve, "CHOLMOD");
    const auto outcome = solver->factor();
    if (outcome != SparseDirectSolver::Outcome::Factored)
      throw NumericalError(model_.name + ": the centrifugal prestress needs a stiffness matrix that is "
                           "positive definite (a substructure restrained against rigid-body motion); "
                           "CHOLMOD: " + solver->failure() +
                           ". Add boundary conditions or set \"Stress Stiffening\" to false");
    auto u1 = Teuchos::rcp(new MultiVector(ownedMap_, 1));
    solver->solve(*fSolve, *u1);
    // K (with the attachment held) is what the reduction factors next
    // (theory §11.4): offered to it, unless free hinges' springs made the
    // matrix solved here a different one.
    if (plainK && prestress_.keepFactor) {
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
      auto kept = std::make_shared<HeldFactor>();
      kept->solver = solver;
      kept->matrix = Ksolve;
      kept->base = out_.K;
      kept->held = std::move(rows);
      // L as allocated, and the held copy of K when it is one (12 bytes an
      // entry, 8 a row): the same on every rank.
      kept->bytes = solver->factorBytes() +
                    (heldRows.empty() ? 0.0
                                      : 12.0 * static_cast<double>(Ksolve->getGlobalNumEntries()) +
                                            8.0 * static_cast<double>(Ksolve->getGlobalNumRows()));
      out_.stiffnessFactor = std::move(kept);
    }
    checkFreeHingesBalance(*u1, *f);
    if (!heldRows.empty()) recordReactions(*u1, *f, heldRows, heldDofs);
    return u1;
  }

  /// The hinge rotation phi = (theta_b,k - theta_a,k) / n_k of a pair as
  /// rows and coefficients (theta_a,k may be fixed: then one row).
  std::vector<std::pair<long long, double>> hingeRotationRows(const HingePair& p) const {
    std::vector<std::pair<long long, double>> w;
    expand(p.b, 3 + p.k, 1.0 / p.n[p.k], w);
    expand(p.a, 3 + p.k, -1.0 / p.n[p.k], w);
    return w;
  }

  /// A free hinge (no spring) is a mechanism, and K is singular. Its
  /// steady state at the undeformed position exists only when the
  /// centrifugal loads have no moment about it (a balanced blade, theory
  /// §17.2); the static solve then holds each free hinge with a spring
  /// k_s w w^T of K's own scale (the RMS entry), which carries nothing, and
  /// checkFreeHingesBalance verifies that. Collective (the norm).
  Teuchos::RCP<const CrsMatrix> holdFreeHinges() {
    bool anyFree = false;
    for (const HingePair& p : hingePairs_) anyFree = anyFree || model_.hinges[p.hinge].stiffness == 0.0;
    if (!anyFree) return out_.K;
    freeHingeStiffness_ = out_.K->getFrobeniusNorm() / std::sqrt(static_cast<double>(out_.layout.size));
    auto K = Teuchos::rcp(new CrsMatrix(*out_.K, Teuchos::Copy));
    K->resumeFill();
    for (const HingePair& p : hingePairs_) {
      if (model_.hinges[p.hinge].stiffness != 0.0) continue;
      const auto w = hingeRotationRows(p);
      for (const auto& [r, wr] : w) {
        if (ownedMap_->getLocalElement(static_cast<GO>(r)) == Teuchos::OrdinalTraits<LO>::invalid()) continue;
        std::vector<GO> cols;
        std::vector<double> vals;
        for (const auto& [c, wc] : w) cols.push_back(static_cast<GO>(c)), vals.push_back(freeHingeStiffness_ * wr * wc);
        K->sumIntoGlobalValues(static_cast<GO>(r), Teuchos::ArrayView<const GO>(cols),
                               Teuchos::ArrayView<const double>(vals));
      }
    }
    K->fillComplete(ownedMap_, ownedMap_);
    return K;
  }

  /// The moment k_s phi each free hinge needed in the static solve must be
  /// zero to rounding: below 1e-9 of the load's own moment scale
  /// ||f||_1 times the model's extent. Otherwise the loads turn the blade
  /// about the hinge and the undeformed position is no steady state.
  /// Collective.
  void checkFreeHingesBalance(const MultiVector& u1, const MultiVector& f) const {
    if (freeHingeStiffness_ == 0.0) return;
    double extent = 0.0;
    for (int c = 0; c < 3; ++c) {
      double lo = mesh_.x(0)[c], hi = lo;
      for (std::int64_t n = 1; n < numNodes_; ++n) lo = std::min(lo, mesh_.x(n)[c]), hi = std::max(hi, mesh_.x(n)[c]);
      extent = std::max(extent, hi - lo);
    }
    const double scale = f.getVector(0)->norm1() * extent;
    auto uv = u1.getData(0);
    for (const HingePair& p : hingePairs_) {
      if (model_.hinges[p.hinge].stiffness != 0.0) continue;
      double local = 0.0, phi = 0.0;
      for (const auto& [r, w] : hingeRotationRows(p)) {
        const auto lid = ownedMap_->getLocalElement(static_cast<GO>(r));
        if (lid != Teuchos::OrdinalTraits<LO>::invalid()) local += w * uv[lid];
      }
      Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, local, Teuchos::outArg(phi));
      const double moment = freeHingeStiffness_ * std::abs(phi);
      CMS_INPUT_CHECK(moment > 1e-9 * scale,
                      model_.name << ": hinge '" << model_.hinges[p.hinge].name << "' is free (no Stiffness) but the "
                                  << "centrifugal loads have a moment of " << moment << " N m per (rad/s)^2 about it at "
                                  << nodeName(mesh_, p.a)
                                  << ": the blade is not in equilibrium at its undeformed position (no steady "
                                     "state to linearise about). Give the hinge a Stiffness, or set \"Stress "
                                     "Stiffening\" to false");
    }
  }

  /// The force each hold exerts per unit Omega^2, r = K u1 - f, on every
  /// rank (a sum over the owners of the held rows). Collective.
  void recordReactions(const MultiVector& u1, const MultiVector& f, const std::vector<long long>& heldRows,
                       const std::vector<PrestressConditions::NodalValue>& heldDofs) {
    MultiVector r(ownedMap_, 1);
    out_.K->apply(u1, r);
    r.update(-1.0, f, 1.0);
    auto rv = r.getData(0);
    std::vector<double> local(heldRows.size(), 0.0), global(heldRows.size(), 0.0);
    for (std::size_t i = 0; i < heldRows.size(); ++i) {
      const auto lid = ownedMap_->getLocalElement(static_cast<GlobalOrdinal>(heldRows[i]));
      if (lid != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) local[i] = rv[lid];
    }
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
    for (std::size_t i = 0; i < heldDofs.size(); ++i) {
      out_.reactions1.push_back(heldDofs[i]);
      out_.reactions1.back().value = global[i];
    }
  }

  // 9b. The geometric stiffness KS1 of the element stresses of u1 (theory
  // §10), a second pass over the local elements on the same pattern (lumped
  // items carry no stress). Collective: u1's import, the failure reduction
  // and the export.
  void assembleGeometricStiffness(const MultiVector& u1) {
    MultiVector uOverlap(overlapMap_, 1);
    uOverlap.doImport(u1, Tpetra::Import<>(ownedMap_, overlapMap_), Tpetra::INSERT);
    auto u = uOverlap.getData(0);
    const Spin spin = model_.spin->spin;
    Target vKS = target("KS1");
    forLocalItems(
        [&](std::size_t local, Made& made) {
          const Item& it = items_[localItems_[local]];
          if (it.kind != Item::Kind::Frame && it.kind != Item::Kind::Solid) { made.skip = true; return; }
          const auto b = itemDofStart_[local], e = itemDofStart_[local + 1];
          std::vector<double>& ur = made.rows;
          ur.assign(static_cast<std::size_t>(e - b), 0.0);
          for (auto p = b; p < e; ++p) ur[p - b] = itemLids_[p] >= 0 ? u[itemLids_[p]] : 0.0;
          // The element's DOFs: the rows themselves, or T u for an element at a
          // hinge's second node (its slaved DOFs follow the hinge, theory §17).
          const auto t = transforms_.find(local);
          const double* ue = ur.data();
          if (t != transforms_.end()) {
            const ItemTransform& tr = t->second;
            made.dofs.assign(static_cast<std::size_t>(tr.n), 0.0);
            for (int i = 0; i < tr.n; ++i)
              for (int j = 0; j < tr.m; ++j) made.dofs[i] += tr.T[static_cast<std::size_t>(i) * tr.m + j] * ur[j];
            ue = made.dofs.data();
          }
          if (it.kind == Item::Kind::Frame) {
            const FrameElement fe = frameOf(it);
            // N(x) and the shear forces from the element's equilibrium
            // under its own centrifugal load: quadratic along it (theory §10).
            made.m.K = frameGeometricStiffness(fe, frameCentrifugalPrestress(fe, ue, spin));
          } else {
            made.m.K = solidGeometricStiffness(solidOf(it, made.xyz), ue);
          }
        },
        [&](std::size_t local, const Made& made) { scatterItem(local, made.m.K, made.at, vKS); },
        [&](std::size_t local, const std::exception& ex) {
          const Item& it = items_[localItems_[local]];
          failureIsInput_ = dynamic_cast<const InputError*>(&ex) != nullptr;
          failure_ = model_.name + ": element " + std::to_string(it.block->cellTags[it.cell]) + ": " + ex.what();
        });
    throwIfAnyFailed();
    out_.KS1 = finish(vKS);
    addOffsetLoadStiffness();
  }

  /// PrestressConditions::offsetLoads' link stiffness added to KS1: each
  /// rank its owned rows (the list is the same on every rank).
  void addOffsetLoadStiffness() {
    if (prestress_.offsetLoads.empty()) return;
    const DofLayout& L = out_.layout;
    std::map<std::pair<GO, GO>, double> entries;
    for (const auto& o : prestress_.offsetLoads) {
      const bool fitted = !o.rotation[0].empty() || !o.rotation[1].empty() || !o.rotation[2].empty();
      bool rotations = o.node >= 0 && o.node < numNodes_;
      for (int c = 3; c < 6 && rotations; ++c) rotations = (L.present[o.node] & (1u << c)) != 0;
      if (!fitted && !rotations) continue;
      const double fr = o.force[0] * o.arm[0] + o.force[1] * o.arm[1] + o.force[2] * o.arm[2];
      std::vector<std::pair<long long, double>> rows[3];
      for (int i = 0; i < 3; ++i)
        if (!fitted) rows[i] = prestressRows({o.node, static_cast<Component>(3 + i), 0.0}, "offset load");
        else  // theta_i through the fitted rotation's rows (a RigidFit)
          for (const auto& t : o.rotation[static_cast<std::size_t>(i)])
            for (const auto& [r, w] : prestressRows(t, "offset load")) rows[i].push_back({r, w * t.value});
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double k = (i == j ? fr : 0.0) - 0.5 * (o.force[i] * o.arm[j] + o.arm[i] * o.force[j]);
          if (k == 0.0) continue;
          for (const auto& [ri, wi] : rows[i]) {
            if (!ownedMap_->isNodeGlobalElement(static_cast<GO>(ri))) continue;
            for (const auto& [rj, wj] : rows[j]) entries[{static_cast<GO>(ri), static_cast<GO>(rj)}] += wi * wj * k;
          }
        }
    }
    // Sized per row: a hinge's slaved rotation expands into several columns.
    Teuchos::Array<std::size_t> perRow(static_cast<std::size_t>(ownedMap_->getNodeNumElements()), 0);
    for (const auto& [rc, v] : entries) ++perRow[static_cast<std::size_t>(ownedMap_->getLocalElement(rc.first))];
    auto extra = Teuchos::rcp(new CrsMatrix(ownedMap_, perRow()));
    for (const auto& [rc, v] : entries) {
      const GO col = rc.second;
      extra->insertGlobalValues(rc.first, Teuchos::tuple<GO>(col), Teuchos::tuple<double>(v));
    }
    extra->fillComplete(out_.KS1->getDomainMap(), out_.KS1->getRangeMap());
    out_.KS1 = matrixSum(1.0, *out_.KS1, 1.0, *extra);
  }

  const FiniteElementModel& model_;
  const mesh::Mesh& mesh_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  const PrestressConditions& prestress_;
  const std::int64_t numNodes_;
  const int rank_, nranks_;
  AssembledMatrices out_;

  // listItems
  std::vector<Item> items_;
  std::vector<HingePair> hingePairs_;
  // layOutHinges: hinge pair of each second node (-1: none; empty: no hinges)
  std::vector<int> slaveOf_;
  // mapItemRows: local items that touch a hinge's second node
  std::unordered_map<std::size_t, ItemTransform> transforms_;
  std::size_t numElements_ = 0;
  // partitionNodes, mapItemRows: rows and maps
  std::vector<std::size_t> localItems_;  ///< indices into items_ of this rank's items
  std::vector<GO> overlapGids_;          ///< owned rows, then ghost rows
  LO numOwned_ = 0, numOverlap_ = 0;
  Teuchos::RCP<const Map> ownedMap_, overlapMap_, ghostMap_;
  std::vector<std::int64_t> itemDofStart_;  ///< local item k's rows: itemDofs_[itemDofStart_[k] ..]
  std::vector<long long> itemDofs_;
  std::vector<LO> itemLids_;             ///< itemDofs_ as overlap lids (-1: fixed)
  std::vector<LO> rowLid_;               ///< global row -> overlap lid, until the owned pattern is built
  std::vector<long long> ghosts_;
  // buildOverlapPattern, buildOwnedPattern
  Teuchos::ArrayRCP<std::size_t> rowPtr_;
  std::vector<LO> cols_;
  std::size_t ghostBegin_ = 0, ownedNnz_ = 0;
  Teuchos::RCP<Tpetra::Export<>> exporter_, ghostExporter_;
  Teuchos::RCP<const Graph> ghostGraph_, ownedGraph_;
  decltype(std::declval<const Graph&>().getLocalGraphHost()) ownedLocal_;  ///< ownedGraph_'s CSR arrays
  // assembleElements
  bool spinning_ = false, rotatingFrame_ = false, tilt_ = false;
  bool circulatory_ = false;  ///< stationary frame with Rayleigh beta: N1 and KR are assembled
  bool damped_ = false;  ///< some spring item has damping: D is assembled
  double freeHingeStiffness_ = 0.0;  ///< k_s of holdFreeHinges (0: no free hinge)
  Target vM_, vK_, vG_, vKT_, vD_, vN_, vKR_;
  std::vector<double> vf_;
  std::string failure_;
  bool failureIsInput_ = false;  ///< an element's data is bad, not the numerics
};

}  // namespace

int DofLayout::componentCount(std::int64_t node) const {
  const std::uint8_t gone = fixed[node] | (slaved.empty() ? 0 : slaved[node]);
  return __builtin_popcount(present[node] & ~gone);
}

long long DofLayout::row(std::int64_t node, Component c) const {
  const int bit = static_cast<int>(c);
  const std::uint8_t free = present[node] & ~fixed[node] & ~(slaved.empty() ? 0 : slaved[node]);
  if (!(free & (1u << bit))) return -1;
  return first[node] + __builtin_popcount(free & ((1u << bit) - 1u));
}

AssembledMatrices assemble(const FiniteElementModel& model,
                           const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                           const PrestressConditions& prestress) {
  const auto t0 = std::chrono::steady_clock::now();
  model.validate();
  return Assembler(model, comm, prestress).run(t0);
}

}  // namespace cms::fem
