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
/// Every reader stores a cell's nodes in Gmsh's order (gmsh.info, "Node
/// ordering"), whatever its file's order; for the quadratic solids:
///   Hex20 (Gmsh 17): corners 0-7 as Hex8 (bottom 0-3 counter-clockwise seen
///     from the top, top 4-7 above them), then mid-edge nodes on the corner
///     pairs (0,1) (0,3) (0,4) (1,2) (1,5) (2,3) (2,6) (3,7) (4,5) (4,7) (5,6) (6,7).
///     Abaqus/CalculiX C3D20(R) numbers its mid-edge nodes 9-20 on (1,2) (2,3)
///     (3,4) (4,1) (5,6) (6,7) (7,8) (8,5) (1,5) (2,6) (3,7) (4,8) (1-based),
///     so Gmsh node 8+k is deck node 9 + {0,3,8,1,9,2,10,11,4,7,5,6}[k].
///   Wedge15 (Gmsh 18, "prism"): corners 0-2 (bottom triangle), 3-5 above
///     them, then mid-edge nodes on (0,1) (0,2) (0,3) (1,2) (1,4) (2,5) (3,4)
///     (3,5) (4,5). C3D15 numbers them 7-15 on (1,2) (2,3) (3,1) (4,5) (5,6)
///     (6,4) (1,4) (2,5) (3,6), so Gmsh node 6+k is deck node
///     7 + {0,2,6,1,7,8,3,5,4}[k].
/// Corners of Tet4/Tet10/Hex8/Hex20/Wedge15 are in the same order in both.
///   Hex27, Hex64, Hex125 (Gmsh 12, 92, 93: Lagrange hexahedra of order 2,
///     3, 4): the reader does NOT keep Gmsh's order (corners, edges, faces,
///     interior, each recursively) but puts the nodes in lexicographic order
///     of their reference positions, node (i, j, l) of the (k+1)^3 grid of
///     [-1, 1]^3 at i + (k+1) j + (k+1)^2 l (the Gmsh reader module from
///     Gmsh's own reference coordinates, getElementProperties; the reader
///     without Gmsh from a table of them, held to the same result by
///     MeshReader.NativeAndGmshReadersAgree); cms/fem/SolidElement.hpp uses
///     that order.
enum class CellType { Point1, Line2, Line3, Tri3, Tri6, Quad4, Tet4, Tet10, Hex8, Hex20, Wedge15, Hex27, Hex64, Hex125, Other };

/// The order k of a Lagrange hexahedron (Hex27 2, Hex64 3, Hex125 4); 0 for
/// every other cell.
inline int lagrangeHexOrder(CellType type) {
  return type == CellType::Hex27 ? 2 : type == CellType::Hex64 ? 3 : type == CellType::Hex125 ? 4 : 0;
}

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
  /// The element name of the file when it says more than the shape (an
  /// Abaqus/CalculiX deck's "C3D20R", "C3D8I"); empty for Gmsh. The model
  /// (fem) may take an element set's default formulation from it.
  std::string elementName;

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
  /// What the reader skipped or assumed, one line each ("deck.inp:12:
  /// ..."), for a driver to print: an .inp deck's keywords that are not
  /// mesh, parameters ignored, ids a GENERATE range named but the deck does
  /// not define. Empty for Gmsh meshes.
  std::vector<std::string> notes;
  /// Group names compared in any case (an .inp deck's, as Abaqus and
  /// CalculiX read them: *NSET ROOT and *ELSET Root are one name); Gmsh's
  /// physical names are compared as spelled.
  bool namesIgnoreCase = false;

  std::size_t nodeCount() const { return nodeTags.size(); }
  const double* x(std::int64_t node) const { return &coordinates[3 * node]; }

  /// The group of that name, the one above dimension 0 where a node set
  /// (dimension 0) shares it; throws cms::InputError naming the file, the
  /// missing name and the names available, or the dimensions of two groups
  /// above 0 that share the name (which one is meant cannot be told).
  const PhysicalGroup& group(const std::string& name) const;
  bool hasGroup(const std::string& name) const;
  /// Sorted, unique node indices of every cell of the group (a node set).
  /// Where two groups share the name (an .inp deck's *NSET and *ELSET of one
  /// name, which Abaqus keeps apart), the one of dimension 0 is the node set.
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

/// A mesh file by its extension: .inp (any case) through readInp
/// (InpReader.hpp; `parameters` must then be empty), anything else through
/// readGmsh. Where a scene or a driver takes a mesh file, it takes it here.
Mesh readMesh(const std::string& path, const std::map<std::string, double>& parameters = {});

}  // namespace cms::mesh
