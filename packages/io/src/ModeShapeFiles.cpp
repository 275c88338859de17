#include "cms/io/ModeShapeFiles.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>

#include <Teuchos_Comm.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"

namespace cms::io {

namespace {

/// Text as an XML attribute value: a scene named "R&D <rig>" made a .pvd
/// ParaView could not read (found by a review).
std::string xmlAttribute(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

/// VTK cell type and the Gmsh-to-VTK node order of each supported cell.
int vtkType(fem::CellType t) {
  switch (t) {
    case fem::CellType::Point1: return 1;
    case fem::CellType::Line2: return 3;
    case fem::CellType::Tet4: return 10;
    case fem::CellType::Tet10: return 24;
    case fem::CellType::Hex8: return 12;
    case fem::CellType::Hex20: return 25;    // VTK_QUADRATIC_HEXAHEDRON
    case fem::CellType::Wedge15: return 26;  // VTK_QUADRATIC_WEDGE
    default: return 0;
  }
}

/// The VTK position of Gmsh's node i. Gmsh's Tet10 numbers the last two edge
/// nodes (2,3), (1,3); VTK (1,3), (2,3). VTK numbers the edge nodes of
/// quadratic hexahedra and wedges as Abaqus does (cms/mesh/Mesh.hpp gives
/// that permutation).
int vtkNode(fem::CellType t, int i) {
  static const int hex20[12] = {0, 3, 8, 1, 9, 2, 10, 11, 4, 7, 5, 6};
  static const int wedge15[9] = {0, 2, 6, 1, 7, 8, 3, 5, 4};
  if (t == fem::CellType::Tet10 && (i == 8 || i == 9)) return i == 8 ? 9 : 8;
  if (t == fem::CellType::Hex20 && i >= 8) return 8 + hex20[i - 8];
  if (t == fem::CellType::Wedge15 && i >= 6) return 6 + wedge15[i - 6];
  return i;
}

/// A distributed two-column vector gathered to every rank, by global row.
std::vector<std::array<double, 2>> gather(const MultiVector& u) {
  const auto map = u.getMap();
  auto rep = Teuchos::rcp(new Map(map->getGlobalNumElements(), 0, map->getComm(), Tpetra::LocallyReplicated));
  MultiVector r(rep, 2);
  r.doImport(u, Tpetra::Import<>(map, rep), Tpetra::INSERT);
  std::vector<std::array<double, 2>> out(rep->getNodeNumElements());
  auto re = r.getData(0), im = r.getData(1);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {re[i], im[i]};
  return out;
}

/// A hinge's second node has one row, its rotation about the coordinate
/// axis k closest to the hinge axis n (theory §17.1): its translations are
/// its partner's (the coincident node of the first set) and its other
/// rotations theta_a,j + (n_j / n_k)(theta_b,k - theta_a,k). Filled in here
/// so that the file shows the joint moving with the blade.
void followHinge(const fem::Mesh& mesh, const fem::HingeSet& h, long long base,
                 std::vector<std::array<double, 6>>& re, std::vector<std::array<double, 6>>& im) {
  const auto first = mesh.nodeSet(h.nodeSet), second = mesh.nodeSet(h.toNodeSet);
  const fem::Vec3 n = fem::unit(h.axis);
  int k = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(n[d]) > std::abs(n[k])) k = d;
  for (std::int64_t b : second) {
    std::int64_t a = -1;
    double best = 0.0;
    for (std::int64_t c : first) {  // the partner: the nearest (coincident) node
      double d2 = 0.0;
      for (int d = 0; d < 3; ++d) d2 += std::pow(mesh.coordinates[3 * c + d] - mesh.coordinates[3 * b + d], 2);
      if (a < 0 || d2 < best) a = c, best = d2;
    }
    if (a < 0) continue;
    for (auto* v : {&re, &im}) {
      const std::array<double, 6> ua = (*v)[base + a];
      std::array<double, 6>& ub = (*v)[base + b];
      const double turn = ub[3 + k] - ua[3 + k];  // n_k phi
      for (int c = 0; c < 3; ++c) ub[c] = ua[c];
      for (int j = 0; j < 3; ++j)
        if (j != k) ub[3 + j] = ua[3 + j] + n[j] / n[k] * turn;
    }
  }
}

}  // namespace

std::vector<std::string> writeModeShapes(OutputFiles& files, const synthesis::AssembledStructure& structure,
                                         const synthesis::SynthesizedStructure& synthesis,
                                         const synthesis::StructureModes& modes, const std::string& directory,
                                         const std::string& name) {
  const bool root = structure.comm()->getRank() == 0;
  std::vector<std::string> written;
  // Nothing here throws on rank 0 alone (the other ranks would wait in the
  // next mode's gather: a hang, found by a review): a directory or file
  // that cannot be made shows when `files` is committed, on every rank.
  std::error_code ec;
  if (root) std::filesystem::create_directories(directory, ec);
  const std::size_t ns = structure.numSubstructures();
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (std::size_t m = 0; m < modes.result.modes.size(); ++m) {
    const auto u = synthesis.expand(modes, static_cast<int>(m));
    // Points, cells and the displacement of every point, substructure by substructure.
    std::vector<std::array<double, 3>> points;
    std::vector<std::array<double, 6>> re, im;  // ux uy uz rx ry rz
    std::vector<int> cellType, cellPart;
    std::vector<std::vector<long long>> cells;
    for (std::size_t k = 0; k < ns; ++k) {
      const auto values = gather(*u[k]);  // collective
      const long long base = static_cast<long long>(points.size());
      const auto* sub = structure.assembled(k);
      if (!sub) {  // rigid rotor: a vertex at its centre with a = (u_P, theta)
        points.push_back(structure.attachmentPoint(k));
        std::array<double, 6> r{}, i{};
        for (int c = 0; c < 6; ++c) r[c] = values[c][0], i[c] = values[c][1];
        re.push_back(r), im.push_back(i);
        cells.push_back({base}), cellType.push_back(1), cellPart.push_back(static_cast<int>(k));
        continue;
      }
      const auto& t = sub->dofs();
      for (std::size_t n = 0; n < t.nodes(); ++n) {
        points.push_back({t.coordinates[3 * n], t.coordinates[3 * n + 1], t.coordinates[3 * n + 2]});
        std::array<double, 6> r{}, i{};
        for (long long row = t.offsets[n]; row < t.offsets[n + 1]; ++row) {
          const int c = static_cast<int>(t.components[row]);
          r[c] = values[row][0], i[c] = values[row][1];
        }
        re.push_back(r), im.push_back(i);
      }
      const fem::Mesh& mesh = *structure.substructure(k).model->mesh;
      for (const auto& h : structure.substructure(k).model->hinges) followHinge(mesh, h, base, re, im);
      for (const auto& es : structure.substructure(k).model->elementSets)
        for (const auto& b : mesh.group(es.group).blocks) {
          if (const int p = mesh::lagrangeHexOrder(b.type)) {
            // Drawn as its p^3 sub-hexahedra between neighbouring nodes: every
            // node's value is written, and no reader has to agree with VTK
            // on the node order of its Lagrange cells (which changed in VTK 9).
            const int m = p + 1;
            for (std::size_t c = 0; c < b.size(); ++c) {
              const std::int64_t* cn = &b.nodes[c * b.nodesPerCell];
              auto at = [&](int i, int j, int l) { return base + cn[i + m * (j + m * l)]; };
              for (int l = 0; l < p; ++l)
                for (int j = 0; j < p; ++j)
                  for (int i = 0; i < p; ++i) {
                    cells.push_back({at(i, j, l), at(i + 1, j, l), at(i + 1, j + 1, l), at(i, j + 1, l),
                                     at(i, j, l + 1), at(i + 1, j, l + 1), at(i + 1, j + 1, l + 1),
                                     at(i, j + 1, l + 1)});
                    cellType.push_back(12), cellPart.push_back(static_cast<int>(k));
                  }
            }
            continue;
          }
          const int vt = vtkType(b.type);
          if (vt == 0) continue;
          for (std::size_t c = 0; c < b.size(); ++c) {
            std::vector<long long> cell(b.nodesPerCell);
            for (int a = 0; a < b.nodesPerCell; ++a)
              cell[vtkNode(b.type, a)] = base + b.nodes[c * b.nodesPerCell + a];
            cells.push_back(cell), cellType.push_back(vt), cellPart.push_back(static_cast<int>(k));
          }
        }
    }
    if (!root) continue;
    const std::string file = name + "-mode-" + std::to_string(m + 1) + ".vtu";
    const auto path = std::filesystem::path(directory) / file;
    {
      auto& o = files.open(path);
      o << std::setprecision(10);
      const auto& md = modes.result.modes[m];
      o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <UnstructuredGrid>\n    <FieldData>\n"
        << "      <DataArray type=\"Float64\" Name=\"frequency_hz\" NumberOfTuples=\"1\" format=\"ascii\">" << md.hz
        << "</DataArray>\n      <DataArray type=\"Float64\" Name=\"growth_rate\" NumberOfTuples=\"1\" format=\"ascii\">"
        << md.growthRate << "</DataArray>\n    </FieldData>\n"
        << "    <Piece NumberOfPoints=\"" << points.size() << "\" NumberOfCells=\"" << cells.size() << "\">\n"
        << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (const auto& p : points) o << "          " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
      o << "        </DataArray>\n      </Points>\n      <PointData Vectors=\"displacement_real\">\n";
      const char* names[4] = {"displacement_real", "displacement_imag", "rotation_real", "rotation_imag"};
      for (int f = 0; f < 4; ++f) {
        const auto& v = f % 2 ? im : re;
        const int off = f < 2 ? 0 : 3;
        o << "        <DataArray type=\"Float64\" Name=\"" << names[f] << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
        for (const auto& x : v) o << "          " << x[off] << ' ' << x[off + 1] << ' ' << x[off + 2] << '\n';
        o << "        </DataArray>\n";
      }
      o << "      </PointData>\n      <CellData Scalars=\"substructure\">\n"
        << "        <DataArray type=\"Int32\" Name=\"substructure\" format=\"ascii\">\n         ";
      for (int p : cellPart) o << ' ' << p;
      o << "\n        </DataArray>\n      </CellData>\n      <Cells>\n"
        << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
      for (const auto& c : cells) {
        o << "         ";
        for (long long v : c) o << ' ' << v;
        o << '\n';
      }
      o << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n         ";
      long long off = 0;
      for (const auto& c : cells) o << ' ' << (off += static_cast<long long>(c.size()));
      o << "\n        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n         ";
      for (int tpe : cellType) o << ' ' << tpe;
      o << "\n        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    }
    written.push_back(path.string());
    pvd << "    <DataSet timestep=\"" << m + 1 << "\" part=\"0\" file=\"" << xmlAttribute(file) << "\"/>\n";
  }
  if (root) {
    pvd << "  </Collection>\n</VTKFile>\n";
    const auto path = std::filesystem::path(directory) / (name + "-modes.pvd");
    files.open(path) << pvd.str();
    written.push_back(path.string());
  }
  return written;
}

}  // namespace cms::io
