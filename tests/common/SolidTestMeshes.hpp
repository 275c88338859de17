// Small structured solid meshes for element tests, built in code: a hex grid,
// its split into tetrahedra (Kuhn) or wedges, and the quadratic elements with
// a node at the midpoint of every edge (shared between cells), all in Gmsh's
// node order (cms/mesh/Mesh.hpp). The edge tables are the tests' own copies
// of Gmsh's orders, checked against Gmsh's meshes by the Gmsh* tests of
// tests/unit/fem/SolidElementTest.cpp.
#pragma once

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "cms/fem/SolidElement.hpp"

namespace cms::fixtures {

/// Tet10 edge nodes 4..9, Hex20 edge nodes 8..19, Wedge15 edge nodes 6..14.
constexpr int kTet10Edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
constexpr int kHex20Edges[12][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
                                    {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
constexpr int kWedge15Edges[9][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 4},
                                     {2, 5}, {3, 4}, {3, 5}, {4, 5}};

struct TestMesh {
  fem::SolidType type = fem::SolidType::Hex8;
  std::vector<double> xyz;
  std::vector<std::vector<int>> cells;
  int nodes() const { return static_cast<int>(xyz.size() / 3); }
};

/// Structured hex grid of [x0, x0 + Lx] x [y0, y0 + Ly] x [z0, z0 + Lz], Gmsh node order per cell.
inline TestMesh hexGrid(int nx, int ny, int nz, double Lx, double Ly, double Lz, double x0 = 0.0,
                        double y0 = 0.0, double z0 = 0.0) {
  TestMesh m;
  auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.xyz.insert(m.xyz.end(), {x0 + Lx * i / nx, y0 + Ly * j / ny, z0 + Lz * k / nz});
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.cells.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                           id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
                           id(i, j + 1, k + 1)});
  return m;
}

/// Kuhn's split of every hex into six positively oriented tets around the
/// diagonal 0-6; conforming between translated cells.
inline TestMesh toTet4(const TestMesh& hex) {
  static const int kuhn[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                 {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  TestMesh m;
  m.type = fem::SolidType::Tet4;
  m.xyz = hex.xyz;
  for (const auto& c : hex.cells)
    for (const auto& t : kuhn) m.cells.push_back({c[t[0]], c[t[1]], c[t[2]], c[t[3]]});
  return m;
}

/// Every hex split into two wedges along its 0-2 / 4-6 diagonal plane
/// (bottom triangles counter-clockwise seen from +z, the top above them);
/// conforming between translated cells. The linear wedges are only an
/// intermediate (corners of Wedge15).
inline TestMesh toWedgeCorners(const TestMesh& hex) {
  TestMesh m;
  m.type = fem::SolidType::Wedge15;
  m.xyz = hex.xyz;
  for (const auto& c : hex.cells) {
    m.cells.push_back({c[0], c[1], c[2], c[4], c[5], c[6]});
    m.cells.push_back({c[0], c[2], c[3], c[4], c[6], c[7]});
  }
  return m;
}

/// The quadratic mesh: a node at the midpoint of every edge of the table
/// (shared between cells), appended to each cell in the table's order.
template <std::size_t E>
TestMesh withEdgeNodes(const TestMesh& linear, const int (&edges)[E][2], fem::SolidType type) {
  TestMesh m;
  m.type = type;
  m.xyz = linear.xyz;
  std::map<std::pair<int, int>, int> mid;
  for (auto c : linear.cells) {
    const std::vector<int> corners = c;
    for (const auto& e : edges) {
      const int a = corners[e[0]], b = corners[e[1]];
      const std::pair<int, int> key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it == mid.end()) {
        it = mid.emplace(key, m.nodes()).first;
        for (int i = 0; i < 3; ++i) m.xyz.push_back(0.5 * (m.xyz[3 * a + i] + m.xyz[3 * b + i]));
      }
      c.push_back(it->second);
    }
    m.cells.push_back(c);
  }
  return m;
}

inline TestMesh toTet10(const TestMesh& tet4) { return withEdgeNodes(tet4, kTet10Edges, fem::SolidType::Tet10); }

/// The order k of a Lagrange hex type (Hex27 2, Hex64 3, Hex125 4); 0 otherwise.
inline int lagrangeOrder(fem::SolidType t) {
  return t == fem::SolidType::Hex27 ? 2 : t == fem::SolidType::Hex64 ? 3 : t == fem::SolidType::Hex125 ? 4 : 0;
}

/// Lexicographic index of the Lagrange hex node (i, j, l) (SolidElement.hpp).
inline int lagrangeNode(int k, int i, int j, int l) { return i + (k + 1) * (j + (k + 1) * l); }

/// The (k+1)^3 nodes of a Lagrange hex of order k on the trilinear map of
/// 8 corners (Gmsh's corner order), in lexicographic order: node (i, j, l)
/// at reference point (-1 + 2i/k, -1 + 2j/k, -1 + 2l/k). Interpolated
/// along i, then j, then l, each step exact at its ends and where its two
/// values agree: a node on a face x = 1 gets x = 1 exactly (the patch test
/// tells boundary nodes by exact comparison; thirds summed as shape
/// functions would give 0.9999999999999999).
inline std::vector<double> lagrangeHexNodes(const double* corners, int k) {
  auto lerp = [k](double a, double b, int i) { return i == 0 ? a : i == k ? b : a == b ? a : a + (b - a) * i / k; };
  std::vector<double> x;
  for (int l = 0; l <= k; ++l)
    for (int j = 0; j <= k; ++j)
      for (int i = 0; i <= k; ++i)
        for (int d = 0; d < 3; ++d) {
          const double* c = corners + d;
          const double e00 = lerp(c[0], c[3], i), e10 = lerp(c[9], c[6], i), e01 = lerp(c[12], c[15], i),
                       e11 = lerp(c[21], c[18], i);
          x.push_back(lerp(lerp(e00, e10, j), lerp(e01, e11, j), l));
        }
  return x;
}

/// A hex grid as Lagrange hexes of order k: each cell's nodes on the
/// trilinear map of its corners, shared between cells (a face's nodes
/// depend on that face's corners only; merged by their corners' indices).
inline TestMesh withLagrangeNodes(const TestMesh& hex, fem::SolidType type) {
  const int k = lagrangeOrder(type);
  TestMesh m;
  m.type = type;
  std::map<std::vector<int>, int> index;  // (the cell's corner ids weighted by position) -> node
  for (const auto& c : hex.cells) {
    double corners[24];
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) corners[3 * a + d] = hex.xyz[3 * c[a] + d];
    const std::vector<double> x = lagrangeHexNodes(corners, k);
    std::vector<int> cell;
    for (int l = 0; l <= k; ++l)
      for (int j = 0; j <= k; ++j)
        for (int i = 0; i <= k; ++i) {
          // A node is the trilinear combination of the corners with weights
          // (i, k - i) (j, k - j) (l, k - l): its key is the sorted list of
          // (corner id, weight) pairs with nonzero weight, the same from
          // every cell that shares it.
          std::vector<std::pair<int, int>> w;
          const int wi[2] = {k - i, i}, wj[2] = {k - j, j}, wl[2] = {k - l, l};
          static const int bit[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
          for (int a = 0; a < 8; ++a) {
            const int weight = wi[bit[a][0]] * wj[bit[a][1]] * wl[bit[a][2]];
            if (weight) w.push_back({c[a], weight});
          }
          std::sort(w.begin(), w.end());
          std::vector<int> key;
          for (const auto& [id, weight] : w) key.insert(key.end(), {id, weight});
          auto it = index.find(key);
          if (it == index.end()) {
            it = index.emplace(key, m.nodes()).first;
            const double* y = &x[3 * lagrangeNode(k, i, j, l)];
            m.xyz.insert(m.xyz.end(), y, y + 3);
          }
          cell.push_back(it->second);
        }
    m.cells.push_back(cell);
  }
  return m;
}

/// A hex grid as a mesh of `type` (any SolidType): hexes as they are (Hex8,
/// Hex8Incompatible), with edge nodes (Hex20, Hex20Reduced), with the
/// Lagrange grid of nodes (Hex27, Hex64, Hex125), split into tets (Tet4,
/// Tet10) or wedges (Wedge15).
inline TestMesh fromHexGrid(const TestMesh& hex, fem::SolidType type) {
  using fem::SolidType;
  switch (type) {
    case SolidType::Hex8:
    case SolidType::Hex8Incompatible: {
      TestMesh m = hex;
      m.type = type;
      return m;
    }
    case SolidType::Hex20:
    case SolidType::Hex20Reduced: return withEdgeNodes(hex, kHex20Edges, type);
    case SolidType::Tet4: return toTet4(hex);
    case SolidType::Tet10: return toTet10(toTet4(hex));
    case SolidType::Wedge15: return withEdgeNodes(toWedgeCorners(hex), kWedge15Edges, type);
    case SolidType::Hex27:
    case SolidType::Hex64:
    case SolidType::Hex125: return withLagrangeNodes(hex, type);
  }
  return hex;
}

}  // namespace cms::fixtures
