// The sidecar of a pre-assembled substructure: its DOF layout (which node and
// component each matrix row is), node coordinates, node sets, and the Matrix
// Market files holding its matrices, so matrices exported from another FE
// code (CalculiX, Nastran via conversion) can be used as a substructure, and
// any substructure can be written back out (doc/user-guide.md, "Matrix
// Market substructures"). Format, one record per line, '#' starts a comment:
//
//   cms-substructure 1                 first non-comment line: magic, version
//   units SI                           optional; SI is the only system so far
//   matrix K K.mtx                     name and path (relative to the sidecar)
//   matrix M M.mtx                       names: M K G1 KT1 KS1 (see theory §9)
//   spin-axis 0 0 1                    optional: axis of the per-unit-speed matrices
//   spin-origin 0 0 0                  optional
//   node 12 0.0 0.5 1.0 ux uy uz       node id, x y z, its DOF components in
//   node 13 0.0 0.6 1.0 ux uy uz rx ry rz   matrix row order; rows are numbered
//                                      consecutively through the node records
//   node 14 0.0 0.7 1.0                a node without rows (all its DOFs fixed):
//                                      kept for node sets and output
//   set root 12 13                     a named node set (node ids)
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace cms::fem {

/// Components of a node's displacement: translations, then small rotations.
enum class Component : int { UX = 0, UY = 1, UZ = 2, RX = 3, RY = 4, RZ = 5 };
const char* componentName(Component c);
/// The component named s ("ux" .. "rz"); false if s names none.
bool parseComponent(const std::string& s, Component& c);

struct MatrixSubstructureFile {
  std::string path;                                 ///< the sidecar itself
  std::string units = "SI";
  std::map<std::string, std::string> matrices;      ///< name -> path (resolved against the sidecar's folder on read)
  bool hasSpinAxis = false;
  std::array<double, 3> spinAxis{0, 0, 1}, spinOrigin{0, 0, 0};
  std::vector<long long> nodeIds;                   ///< in file order
  std::vector<double> coordinates;                  ///< 3 per node
  std::vector<std::vector<Component>> components;   ///< per node, in row order
  std::map<std::string, std::vector<long long>> nodeSets;

  /// Total rows = sum of components over nodes.
  long long dofCount() const;
  /// First matrix row of each node (size nodeIds.size() + 1).
  std::vector<long long> rowOffsets() const;
};

/// Throws cms::InputError naming the file and line: bad magic or version,
/// unknown record, unknown matrix name, duplicate node id or component,
/// unknown component, non-finite number, set naming an unknown node,
/// no nodes, no K or no M matrix, truncated record.
MatrixSubstructureFile readMatrixSubstructureFile(const std::string& path);

/// Writes the sidecar (matrix paths written as given). Throws cms::InputError
/// if the file cannot be written.
void writeMatrixSubstructureFile(const MatrixSubstructureFile& file, const std::string& path);

}  // namespace cms::fem
