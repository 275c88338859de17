// A finite-element mesh as read from a Gmsh file: node coordinates and the
// cells of each physical group. Physical groups name element sets (material,
// section) and node sets (boundary conditions, interface and attachment
// nodes); which is which is decided by the model that uses the mesh
// (FiniteElementModel), not here. Every rank holds the whole mesh: it is small
// beside the matrices assembled from it (doc/architecture.md, "mesh").
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace cms::mesh {

/// Cell shapes the element library knows, plus Other for anything else (kept
/// so that an element set using it can be reported by name and type).
enum class CellType { Point1, Line2, Line3, Tri3, Tri6, Quad4, Tet4, Tet10, Hex8, Other };

const char* cellTypeName(CellType type);
/// Nodes per cell; 0 for Other.
int cellNodeCount(CellType type);

/// Cells of one type inside one physical group, in Gmsh's node order.
struct CellBlock {
  CellType type = CellType::Other;
  int gmshType = 0;                     ///< Gmsh's element type number
  int nodesPerCell = 0;
  std::vector<std::int64_t> nodes;      ///< nodesPerCell per cell: indices into Mesh::nodeTags
  std::vector<std::size_t> cellTags;    ///< Gmsh element tags, for messages

  std::size_t size() const { return cellTags.size(); }
};

struct PhysicalGroup {
  std::string name;  ///< Gmsh physical name; "<dim>:<tag>" when the group is unnamed
  int dim = 0;
  int tag = 0;
  std::vector<CellBlock> blocks;
};

struct Mesh {
  std::string source;                     ///< file it came from (for messages)
  std::vector<std::size_t> nodeTags;      ///< Gmsh node tag of node index i
  std::vector<double> coordinates;        ///< x, y, z of node index i at 3i..3i+2
  std::vector<PhysicalGroup> groups;

  std::size_t nodeCount() const { return nodeTags.size(); }
  const double* x(std::int64_t node) const { return &coordinates[3 * node]; }

  /// The group of that name; throws cms::InputError naming the file, the
  /// missing name and the names available.
  const PhysicalGroup& group(const std::string& name) const;
  bool hasGroup(const std::string& name) const;
  /// Sorted, unique node indices of every cell of the group (a node set).
  std::vector<std::int64_t> nodeSet(const std::string& name) const;
};

/// Read a Gmsh mesh with Gmsh's own SDK: .msh in formats 2.2 and 4.1, ASCII
/// or binary; a .geo script is run and meshed (dimension of its highest
/// entity) first. Throws cms::InputError naming the file and, where Gmsh or
/// the checks below can tell, the section, entity or node/element tag:
/// unreadable or truncated file, no nodes, no physical groups, a physical
/// group without cells, a cell referring to an unknown node, two nodes at the
/// same coordinates (relative to the mesh size: an unmerged geometry),
/// non-finite coordinates. Gmsh's console output is suppressed. Not
/// thread-safe (Gmsh's SDK is a global state); collective use on every rank
/// is fine since each process has its own. `parameters` set ONELAB numbers
/// "Parameters/<name>" before a .geo script runs, so that a script's
/// `DefineConstant[h = {0.02, Name "Parameters/h"}]` takes the given value
/// (a mesh-size study without copies of the script); ignored for .msh files.
Mesh readGmsh(const std::string& path, const std::map<std::string, double>& parameters = {});

}  // namespace cms::mesh
