#include "cms/substructure/Substructure.hpp"

#include "cms/core/MatrixSum.hpp"
#include "cms/core/Redistribution.hpp"
#include "cms/core/SparseProduct.hpp"

#include <algorithm>
#include <cctype>
#include <utility>
#include <vector>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

#include <MatrixMarket_Tpetra.hpp>
#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
#include "cms/fem/FiniteElementAssembly.hpp"

namespace cms::substructure {

namespace {

using fem::Component;

/// Rows owned by contiguous blocks of nodes (Matrix Market files carry no
/// coordinates-based partition; the rows may sit on other ranks than when
/// the substructure was assembled, which changes nothing but the layout).
Teuchos::RCP<const Map> nodeBlockMap(const DofTable& t, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const long long n = static_cast<long long>(t.nodes());
  const int r = comm->getRank(), p = comm->getSize();
  const long long b = t.offsets[n * r / p], e = t.offsets[n * (r + 1) / p];
  return Teuchos::rcp(new Map(static_cast<GlobalOrdinal>(t.rows()), static_cast<std::size_t>(e - b), 0, comm));
}

/// What a substructure matrix must be: M, K, KT1 and KS1 symmetric, G1
/// skew-symmetric (M q'' + G q' + K q = Q). A file that is not is refused: the
/// symmetric solvers read one triangle, and the answer would be silently
/// that of another matrix.
enum class Symmetry { Symmetric, Skew };

/// Checks a Matrix Market file completely on every rank before Tpetra's
/// reader sees it: Tpetra reads on rank 0 only, and a malformed file must
/// give the same error, with its line, on every rank rather than a hang.
void checkMatrixMarketFile(const std::string& path, long long rows, const std::string& key, Symmetry expected) {
  std::error_code ec;
  CMS_INPUT_CHECK(std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec),
                  path << ": not a regular file (a directory?), not a matrix file");
  std::ifstream in(path);
  CMS_INPUT_CHECK(!in, path << ": cannot open matrix file");
  std::string line;
  long long lineNo = 0;
  CMS_INPUT_CHECK(!std::getline(in, line), path << (in.bad() ? ": cannot read the file" : ": empty file"));
  ++lineNo;
  // Tpetra's reader wants the banner at the first column (a leading space
  // made it throw std::invalid_argument, found by the fuzz driver).
  CMS_INPUT_CHECK(line.compare(0, 14, "%%MatrixMarket") != 0,
                  path << ":1: the banner must start with %%MatrixMarket at the first column (banner \"" << line
                       << "\")");
  // Windows line endings: Tpetra's reader keeps the carriage return in the
  // banner's last word and refused the file with a message about its
  // symmetry (a review).
  CMS_INPUT_CHECK(!line.empty() && line.back() == '\r',
                  path << ":1: Windows line endings (CRLF); convert the file to Unix line endings (dos2unix)");
  std::istringstream banner(line);
  std::string magic, object, format, field, symmetry;
  banner >> magic >> object >> format >> field >> symmetry;
  for (auto* s : {&object, &format, &field, &symmetry})
    for (char& c : *s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  CMS_INPUT_CHECK(magic != "%%MatrixMarket" || object != "matrix" || format != "coordinate",
                  path << ":1: not a Matrix Market coordinate matrix (banner \"" << line << "\")");
  CMS_INPUT_CHECK(field != "real" && field != "integer",
                  path << ":1: field \"" << field << "\" must be real or integer");
  CMS_INPUT_CHECK(symmetry != "general" && symmetry != "symmetric" && symmetry != "skew-symmetric",
                  path << ":1: symmetry \"" << symmetry << "\" must be general, symmetric or skew-symmetric");
  CMS_INPUT_CHECK(expected == Symmetry::Symmetric && symmetry == "skew-symmetric",
                  path << ":1: " << key << " is symmetric; the banner says skew-symmetric");
  CMS_INPUT_CHECK(expected == Symmetry::Skew && symmetry == "symmetric",
                  path << ":1: " << key << " is skew-symmetric; the banner says symmetric");
  long long m = -1, n = -1, nnz = -1;
  // Tpetra's reader refuses blank lines ("contains no characters"); so do we,
  // with the line number, on every rank.
  while (std::getline(in, line)) {
    ++lineNo;
    CMS_INPUT_CHECK(line.empty(), path << ":" << lineNo << ": blank line (not accepted in Matrix Market data)");
    if (line[0] == '%') continue;
    std::istringstream size(line);
    std::string extra;
    CMS_INPUT_CHECK(!(size >> m >> n >> nnz) || (size >> extra) || m < 0 || n < 0 || nnz < 0,
                    path << ":" << lineNo << ": size line must be \"rows columns entries\"");
    break;
  }
  CMS_INPUT_CHECK(m < 0, path << ": no size line");
  CMS_INPUT_CHECK(m != rows || n != rows, path << ":" << lineNo << ": matrix is " << m << " x " << n
                                               << " but the sidecar lays out " << rows << " DOFs");
  long long count = 0;
  // Each entry's place and line: Tpetra's reader sums repeated entries, so a
  // repeat is refused here (found by a review: K(1,1) read doubled).
  struct Entry {
    unsigned long long place;
    long long line;
    double value;
    bool operator<(const Entry& o) const { return place < o.place; }
  };
  std::vector<Entry> places;
  while (std::getline(in, line)) {
    ++lineNo;
    CMS_INPUT_CHECK(line.empty(), path << ":" << lineNo << ": blank line (not accepted in Matrix Market data)");
    if (line[0] == '%') continue;
    const char* s = line.c_str();
    char* end = nullptr;
    const long long i = std::strtoll(s, &end, 10);
    const bool iOk = end != s;
    s = end;
    const long long j = std::strtoll(s, &end, 10);
    const bool jOk = end != s;
    s = end;
    while (*s == ' ' || *s == '\t') ++s;
    const double v = std::strtod(s, &end);
    // Decimal only: strtod also reads hexadecimal (0x1908B100 = 4.2e8),
    // which Tpetra's stream reads as 0 (found by a review).
    const bool decimal = std::all_of(s, static_cast<const char*>(end),
                                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '+' ||
                                                         c == '-' || c == '.' || c == 'e' || c == 'E'; });
    CMS_INPUT_CHECK(end != s && !decimal,
                    path << ":" << lineNo << ": value \"" << std::string(s, static_cast<const char*>(end))
                         << "\" is not a decimal number");
    const bool vOk = end != s;
    while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
    CMS_INPUT_CHECK(!iOk || !jOk || !vOk || *end != '\0',
                    path << ":" << lineNo << ": entry must be \"row column value\"");
    CMS_INPUT_CHECK(i < 1 || i > m || j < 1 || j > n,
                    path << ":" << lineNo << ": index (" << i << ", " << j << ") outside 1.." << m);
    CMS_INPUT_CHECK(!std::isfinite(v), path << ":" << lineNo << ": value is not finite");
    CMS_INPUT_CHECK(symmetry != "general" && j > i,
                    path << ":" << lineNo << ": a " << symmetry << " file stores the lower triangle only");
    CMS_INPUT_CHECK(symmetry == "skew-symmetric" && i == j && v != 0.0,
                    path << ":" << lineNo << ": skew-symmetric matrix with a nonzero diagonal");
    places.push_back({static_cast<unsigned long long>(i - 1) * static_cast<unsigned long long>(n) +
                          static_cast<unsigned long long>(j - 1),
                      lineNo, v});
    ++count;
  }
  std::sort(places.begin(), places.end());
  for (std::size_t k = 1; k < places.size(); ++k)
    CMS_INPUT_CHECK(places[k].place == places[k - 1].place,
                    path << ":" << places[k].line << ": entry (" << places[k].place / n + 1 << ", "
                         << places[k].place % n + 1 << ") given twice (also line " << places[k - 1].line
                         << "); a Matrix Market reader sums repeats: give each entry once");
  CMS_INPUT_CHECK(count != nnz, path << ": " << count << " entries, but the size line declares " << nnz
                                     << " (truncated file?)");
  if (symmetry != "general") return;  // one triangle: symmetric or skew by its banner
  // A general file's two triangles must mirror each other: A(i, j) = s A(j, i),
  // s = 1 or -1. Tolerance: 1e-6 of the larger of the two, so that a
  // matrix printed to 7 significant digits by another tool is accepted,
  // and differences below 1e-12 of the file's largest entry are ignored
  // (an entry written on one side only at the rounding level of the
  // assembly: a perturbation far below the solvers' own backward error).
  double largest = 0.0;
  for (const Entry& e : places) largest = std::max(largest, std::abs(e.value));
  const double sign = expected == Symmetry::Symmetric ? 1.0 : -1.0;
  for (const Entry& e : places) {
    const unsigned long long i = e.place / static_cast<unsigned long long>(n),
                             j = e.place % static_cast<unsigned long long>(n);
    const auto mirror = std::lower_bound(places.begin(), places.end(), Entry{j * static_cast<unsigned long long>(n) + i, 0, 0.0});
    const bool found = mirror != places.end() && mirror->place == j * static_cast<unsigned long long>(n) + i;
    const double other = found ? mirror->value : 0.0;
    const double gap = std::abs(e.value - sign * other);
    if (!(gap > 1e-6 * std::max(std::abs(e.value), std::abs(other)) && gap > 1e-12 * largest)) continue;
    CMS_INPUT_CHECK(i == j, path << ":" << e.line << ": " << key << " must be skew-symmetric, but its diagonal entry ("
                                 << i + 1 << ", " << i + 1 << ") = " << std::setprecision(17) << e.value);
    std::ostringstream os;
    os << path << ":" << e.line << ": " << key << " must be " << (expected == Symmetry::Symmetric ? "symmetric" : "skew-symmetric")
       << ", but entry (" << i + 1 << ", " << j + 1 << ") = " << std::setprecision(17) << e.value
       << " and (" << j + 1 << ", " << i + 1 << ") = " << other;
    if (found) os << " (line " << mirror->line << ")";
    else os << " (absent)";
    os << "; the two triangles must agree to 1e-6";
    throw InputError(os.str());
  }
}

}  // namespace

const char* toString(Matrix a) {
  switch (a) {
    case Matrix::M: return "M";
    case Matrix::K: return "K";
    case Matrix::G1: return "G1";
    case Matrix::KT1: return "KT1";
    case Matrix::KS1: return "KS1";
    case Matrix::K2: return "K2";
    case Matrix::D: return "D";
    case Matrix::N1: return "N1";
  }
  return "?";
}

Teuchos::RCP<const CrsMatrix> Substructure::source(Matrix a) const {
  if (prototype_) {
    const auto& p = *prototype_;
    switch (a) {
      case Matrix::M: return p.M;
      case Matrix::K: return p.K;
      case Matrix::G1: return p.G1;
      case Matrix::KT1: return p.KT1;
      case Matrix::KS1: return p.KS1;
      case Matrix::K2: return p.K2;
      case Matrix::D: return p.D;
      case Matrix::N1: return p.N1;
    }
  }
  switch (a) {
    case Matrix::M: return M_;
    case Matrix::K: return K_;
    case Matrix::G1: return G1_;
    case Matrix::KT1: return KT1_;
    case Matrix::KS1: return KS1_;
    case Matrix::K2: return K2_;
    case Matrix::D: return D_;
    case Matrix::N1: return N1_;
  }
  return Teuchos::null;
}

Teuchos::RCP<const CrsMatrix> Substructure::matrix(Matrix a) const {
  if (prototype_)
    throw std::logic_error("substructure '" + name_ + "': its " + toString(a) +
                           " is its prototype's turned and not formed (theory §15.2): apply() it, or formed()");
  return source(a);
}

bool Substructure::has(Matrix a) const { return !source(a).is_null(); }

void Substructure::apply(Matrix a, const MultiVector& X, MultiVector& Y, double alpha, double beta) const {
  const auto A = source(a);
  if (A.is_null()) throw std::logic_error("substructure '" + name_ + "' has no " + toString(a) + " to apply");
  if (!prototype_) {
    multiply(*A, X, Y, alpha, beta);
    return;
  }
  // Q A_p Q^T X (theory §15.2): the rows turned back into the prototype's
  // axes, its matrix, the result turned into the copy's. The copy's rows
  // are the prototype's (the same map and table).
  const auto& p = *prototype_;
  const auto& R = p.turn.R;
  const std::size_t nc = X.getNumVectors();
  // (The same choice on every rank: triples are kept on all or none, and
  // isSameAs is collective.)
  if (p.triples.empty() || !X.getMap()->isSameAs(*map_) || !Y.getMap()->isSameAs(*map_)) {
    fem::Rotation back;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) back.R[i][j] = R[j][i];
    const auto Xp = turnedRows(X, dofs_, A->getDomainMap(), back);
    MultiVector AX(A->getRangeMap(), nc);
    multiply(*A, *Xp, AX);
    Y.update(alpha, *turnedRows(AX, dofs_, Y.getMap(), p.turn), beta);
    return;
  }
  // Every node triple local: (Q^T x)_c = sum_e R_ec x_e, then
  // (Q y)_c = sum_e R_ce y_e, row by row: out = a (turned in) + b out.
  const std::size_t n = p.triples.size();
  const auto turn = [&](const auto& in, const auto& out, bool back, double a, double b) {
    for (std::size_t j = 0; j < nc; ++j)
      for (std::size_t l = 0; l < n; ++l) {
        const auto& t = p.triples[l];
        const int c = p.places[l];
        double v = 0.0;
        for (int e = 0; e < 3; ++e)
          if (t[e] >= 0) v += (back ? R[e][c] : R[c][e]) * in(static_cast<std::size_t>(t[e]), j);
        out(l, j) = a * v + (b == 0.0 ? 0.0 : b * out(l, j));
      }
  };
  MultiVector Xp(map_, nc, false), AX(map_, nc, false);
  turn(X.getLocalViewHost(Tpetra::Access::ReadOnly), Xp.getLocalViewHost(Tpetra::Access::OverwriteAll), true, 1.0,
       0.0);
  multiply(*A, Xp, AX);
  turn(AX.getLocalViewHost(Tpetra::Access::ReadOnly), Y.getLocalViewHost(Tpetra::Access::ReadWrite), false, alpha,
       beta);
}

double Substructure::frobeniusNorm(Matrix a) const {
  const auto A = source(a);
  return A.is_null() ? 0.0 : A->getFrobeniusNorm();
}

void Substructure::finishConstruction() {
  if (prototype_) {  // K2 is the prototype's (source()); M applied turned
    mass_ = translationMass(*this);
    return;
  }
  // K2 = KS1 - KT1 (theory §9): formed once, so that each speed of a sweep
  // costs one matrix addition.
  // One pattern (an assembled model's matrices share their graph): K2 on
  // it too (matrixSum), instead of MatrixMatrix::add's new graph (a third of
  // a matrix's memory: 29 MiB on the 54,000-DOF bar; the same values, ks -
  // kt, to the bit).
  if (!KS1_.is_null() && !KT1_.is_null())
    K2_ = matrixSum(1.0, *KS1_, -1.0, *KT1_);
  else if (!KS1_.is_null()) K2_ = KS1_;
  else if (!KT1_.is_null()) K2_ = Tpetra::MatrixMatrix::add(-1.0, false, *KT1_, 0.0, false, *KT1_);
  mass_ = translationMass(*this);
}

Substructure Substructure::gatheredTo(int owner, const Teuchos::RCP<const Teuchos::Comm<int>>& self) const {
  if (prototype_) return formed().gatheredTo(owner, self);
  Substructure s;
  s.name_ = name_;
  s.dofs_ = dofs_;
  s.spin_ = spin_;
  s.mass_ = mass_;
  s.reactions1_ = reactions1_;
  s.modalDampingRatio_ = modalDampingRatio_;
  s.M_ = gatherToRank(*M_, owner, self);
  s.K_ = gatherToRank(*K_, owner, self);
  if (!KT1_.is_null()) s.KT1_ = gatherToRank(*KT1_, owner, self);
  if (!s.M_.is_null()) s.map_ = s.M_->getRowMap();
  return s;
}

double Substructure::translationMass(const Substructure& s) {
  MultiVector ones(s.map_, 1), Mx(s.map_, 1);
  {
    // Rows of an assembled substructure are not contiguous per rank (slab
    // partition): ask the map for each row's global index.
    auto v = ones.getDataNonConst(0);
    const Map& map = *s.map_;
    for (long i = 0; i < static_cast<long>(v.size()); ++i)
      v[i] = s.dofs_.components[map.getGlobalElement(static_cast<LocalOrdinal>(i))] == Component::UX ? 1.0 : 0.0;
  }
  s.apply(Matrix::M, ones, Mx);
  Teuchos::Array<double> dot(1);
  ones.dot(Mx, dot());
  return dot[0];
}

std::vector<std::int64_t> DofTable::rowNodes() const {
  std::vector<std::int64_t> node(static_cast<std::size_t>(rows()));
  for (std::size_t n = 0; n < nodes(); ++n)
    for (long long r = offsets[n]; r < offsets[n + 1]; ++r) node[r] = static_cast<std::int64_t>(n);
  return node;
}

long long DofTable::row(std::int64_t node, Component c) const {
  for (long long r = offsets[node]; r < offsets[node + 1]; ++r)
    if (components[r] == c) return r;
  return -1;
}

Substructure Substructure::fromFiniteElementModel(const fem::FiniteElementModel& model,
                                                  const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                                  const fem::PrestressConditions& prestress,
                                                  std::shared_ptr<const HeldFactor>* stiffnessFactor) {
  fem::PrestressConditions conditions = prestress;
  conditions.keepFactor = stiffnessFactor != nullptr;
  fem::AssembledMatrices a = fem::assemble(model, comm, conditions);
  if (stiffnessFactor != nullptr) *stiffnessFactor = std::move(a.stiffnessFactor);
  Substructure s;
  s.name_ = model.name;
  s.map_ = a.map;
  s.M_ = a.M;
  s.K_ = a.K;
  s.G1_ = a.G1;
  s.KT1_ = a.KT1;
  s.KS1_ = a.KS1;
  s.spin_ = model.spin;
  s.reactions1_ = a.reactions1;
  s.f1_ = a.f1;
  s.KX1_ = a.KX1;
  // Damping (theory §13.1): the dampers' D, plus Rayleigh alpha M + beta K
  // with the stiffness at rest; the modal ratio is the synthesis's to apply.
  // A stationary-frame rotor's beta is its material's, on what turns with
  // it (K_R, not its bearings' springs), which also gives its circulatory N1.
  s.D_ = a.D;
  s.N1_ = a.N1;
  if (model.damping.alpha != 0.0 || model.damping.beta != 0.0) {
    auto R = Tpetra::MatrixMatrix::add(model.damping.alpha, false, *a.M, model.damping.beta, false,
                                       a.KR.is_null() ? *a.K : *a.KR);
    s.D_ = s.D_.is_null() ? Teuchos::RCP<const CrsMatrix>(R)
                          : Teuchos::RCP<const CrsMatrix>(Tpetra::MatrixMatrix::add(1.0, false, *s.D_, 1.0, false, *R));
  }
  s.modalDampingRatio_ = model.damping.modalRatio;
  const mesh::Mesh& mesh = *model.mesh;
  DofTable& t = s.dofs_;
  t.nodeIds.assign(mesh.nodeTags.begin(), mesh.nodeTags.end());
  t.coordinates = mesh.coordinates;
  t.offsets.assign(mesh.nodeCount() + 1, 0);
  for (std::size_t n = 0; n < mesh.nodeCount(); ++n) {
    for (int c = 0; c < 6; ++c)
      if (a.layout.row(static_cast<std::int64_t>(n), static_cast<Component>(c)) >= 0)
        t.components.push_back(static_cast<Component>(c));
    t.offsets[n + 1] = static_cast<long long>(t.components.size());
  }
  // Node sets: every physical group that is not an element set (interfaces,
  // attachments, supports).
  std::set<std::string> elementGroups;
  for (const auto& e : model.elementSets) elementGroups.insert(e.group);
  for (const auto& g : mesh.groups)
    if (!elementGroups.count(g.name)) t.nodeSets[g.name] = mesh.nodeSet(g.name);
  s.finishConstruction();
  return s;
}

Substructure Substructure::fromMatrixMarket(const std::string& sidecarPath,
                                            const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const fem::MatrixSubstructureFile f = fem::readMatrixSubstructureFile(sidecarPath);
  Substructure s;
  s.name_ = std::filesystem::path(sidecarPath).stem().string();
  DofTable& t = s.dofs_;
  t.nodeIds = f.nodeIds;
  t.coordinates = f.coordinates;
  t.offsets.assign(f.nodeIds.size() + 1, 0);
  for (std::size_t n = 0; n < f.nodeIds.size(); ++n) {
    t.components.insert(t.components.end(), f.components[n].begin(), f.components[n].end());
    t.offsets[n + 1] = static_cast<long long>(t.components.size());
  }
  std::map<long long, std::int64_t> indexOf;
  for (std::size_t n = 0; n < f.nodeIds.size(); ++n) indexOf[f.nodeIds[n]] = static_cast<std::int64_t>(n);
  for (const auto& [name, ids] : f.nodeSets) {
    auto& set = t.nodeSets[name];
    for (long long id : ids) set.push_back(indexOf.at(id));
  }
  const bool perUnitSpeed = f.matrices.count("G1") || f.matrices.count("KT1") || f.matrices.count("KS1");
  CMS_INPUT_CHECK(perUnitSpeed && !f.hasSpinAxis,
                  sidecarPath << ": per-unit-speed matrices (G1, KT1, KS1) need a spin-axis record");
  if (f.hasSpinAxis) {
    fem::SpinDefinition spin;
    spin.spin.axis = f.spinAxis;
    spin.spin.origin = f.spinOrigin;
    spin.stressStiffening = f.matrices.count("KS1") > 0;
    spin.frame = f.matrices.count("KT1") ? fem::SpinDefinition::Frame::Rotating
                                         : fem::SpinDefinition::Frame::Stationary;
    s.spin_ = spin;
  }

  s.map_ = nodeBlockMap(t, comm);
  using Reader = Tpetra::MatrixMarket::Reader<CrsMatrix>;
  auto read = [&](const std::string& key) -> Teuchos::RCP<const CrsMatrix> {
    auto it = f.matrices.find(key);
    if (it == f.matrices.end()) return Teuchos::null;
    checkMatrixMarketFile(it->second, t.rows(), key, key == "G1" ? Symmetry::Skew : Symmetry::Symmetric);
    Teuchos::RCP<const Map> colMap;
    // The checks above are meant to catch everything Tpetra's reader
    // refuses; whatever they miss still becomes an input error naming the
    // file (Tpetra's banner and size-line failures are collective: every
    // rank throws).
    try {
      return Reader::readSparseFile(it->second, s.map_, colMap, s.map_, s.map_, true, false, false);
    } catch (const InputError&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      std::string what = e.what();
      // Tpetra's TEUCHOS_TEST_FOR_EXCEPTION text: source location, then the message.
      const std::size_t at = what.find("Throw test that evaluated to true:");
      if (at != std::string::npos) {
        const std::size_t eol = what.find('\n', at);
        what = eol == std::string::npos ? std::string() : what.substr(eol + 1);
      }
      while (!what.empty() && std::isspace(static_cast<unsigned char>(what.back()))) what.pop_back();
      throw InputError(it->second + ": Tpetra's Matrix Market reader refused the file: " +
                       (what.empty() ? std::string(e.what()) : what));
    }
  };
  s.M_ = read("M");
  s.K_ = read("K");
  s.G1_ = read("G1");
  s.KT1_ = read("KT1");
  s.KS1_ = read("KS1");
  s.finishConstruction();
  return s;
}

std::string Substructure::fileStem() const {
  std::string stem = name_;
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return stem.empty() ? std::string("substructure") : stem;
}

void Substructure::writeMatrixMarket(const std::string& directory) const {
  if (prototype_) return formed().writeMatrixMarket(directory);
  // What the sidecar format has no record for would be lost without a word
  // (read back, the substructure was undamped; found by a review).
  CMS_INPUT_CHECK(!D_.is_null() || modalDampingRatio_ > 0.0,
                  "substructure '" << name_ << "': its damping (" << (D_.is_null() ? "a Modal Damping Ratio" : "D")
                                   << ") has no place in a Matrix Market substructure (theory §13.1): not written");
  const auto comm = map_->getComm();
  const std::string stem = fileStem();
  const std::filesystem::path dir(directory);
  int ok = 1;
  if (comm->getRank() == 0) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    // Writable: a temporary of the sidecar's, opened and removed.
    ok = std::filesystem::is_directory(dir, ec) && std::ofstream(dir / (stem + ".cms.tmp")) ? 1 : 0;
    std::filesystem::remove(dir / (stem + ".cms.tmp"), ec);
  }
  Teuchos::broadcast(*comm, 0, Teuchos::outArg(ok));
  CMS_INPUT_CHECK(!ok, directory << ": cannot write the substructure '" << name_ << "' there");

  fem::MatrixSubstructureFile f;
  f.nodeIds = dofs_.nodeIds;
  f.coordinates = dofs_.coordinates;
  f.components.resize(dofs_.nodes());
  for (std::size_t n = 0; n < dofs_.nodes(); ++n)
    f.components[n].assign(dofs_.components.begin() + dofs_.offsets[n], dofs_.components.begin() + dofs_.offsets[n + 1]);
  for (const auto& [name, nodes] : dofs_.nodeSets) {
    auto& ids = f.nodeSets[name];
    for (auto n : nodes) ids.push_back(dofs_.nodeIds[n]);
  }
  if (spin_) {
    f.hasSpinAxis = true;
    f.spinAxis = spin_->spin.axis;
    f.spinOrigin = spin_->spin.origin;
  }
  // All or nothing: every file goes to <name>.tmp through a stream whose
  // state is checked (Tpetra's file writer does not check its own: a full
  // disk passed unseen), and only when all are whole are they renamed, any
  // file they replace set aside first and put back if a rename fails (the
  // old probe opened the sidecar for writing and emptied it; found by a
  // review).
  namespace fs = std::filesystem;
  const bool root = comm->getRank() == 0;
  std::vector<std::string> files;
  std::string failure;
  using Writer = Tpetra::MatrixMarket::Writer<CrsMatrix>;
  auto write = [&](const char* key, const Teuchos::RCP<const CrsMatrix>& A) {
    if (A.is_null()) return;
    const std::string file = stem + "_" + key + ".mtx";
    f.matrices[key] = file;
    files.push_back(file);
    std::ofstream out;
    if (root) out.open(dir / (file + ".tmp"));
    // Collective (gathered to rank 0, which writes): a throw on rank 0 alone
    // is kept as the failure, so every rank goes on to the same calls.
    try {
      Writer::writeSparse(out, *A, key, name_ + ": " + key + " (cms-substructure; theory §9)");
    } catch (const std::exception& e) {
      if (failure.empty()) failure = (dir / file).string() + ": " + e.what();
    }
    if (root) {
      out.close();
      if (failure.empty() && out.fail()) failure = (dir / file).string() + ": could not be written";
    }
  };
  write("M", M_);
  write("K", K_);
  write("G1", G1_);
  write("KT1", KT1_);
  write("KS1", KS1_);
  files.push_back(stem + ".cms");
  // Rank 0 writes the sidecar and renames; its failure must reach every
  // rank, not leave the others waiting.
  if (root) {
    std::vector<std::pair<fs::path, fs::path>> setAside;  // (name, its replaced copy)
    std::size_t renamed = 0;
    try {
      if (!failure.empty()) throw InputError(failure);
      fem::writeMatrixSubstructureFile(f, (dir / (stem + ".cms.tmp")).string());
      for (const auto& file : files) {
        std::error_code ec;
        if (fs::exists(dir / file, ec)) {
          fs::rename(dir / file, dir / (file + ".replaced"), ec);
          if (ec) throw InputError((dir / file).string() + ": " + ec.message());
          setAside.push_back({dir / file, dir / (file + ".replaced")});
        }
      }
      for (; renamed < files.size(); ++renamed) {
        std::error_code ec;
        fs::rename(dir / (files[renamed] + ".tmp"), dir / files[renamed], ec);
        if (ec) throw InputError((dir / files[renamed]).string() + ": " + ec.message());
      }
      for (const auto& [name, aside] : setAside) {
        std::error_code ec;
        fs::remove(aside, ec);
      }
    } catch (const std::exception& e) {
      failure = e.what();
      std::error_code ec;
      for (std::size_t i = 0; i < renamed; ++i) fs::remove(dir / files[i], ec);  // the new ones out
      for (const auto& [name, aside] : setAside) fs::rename(aside, name, ec);    // the old ones back
      for (const auto& file : files) fs::remove(dir / (file + ".tmp"), ec);
    }
  }
  int len = static_cast<int>(failure.size());
  Teuchos::broadcast(*comm, 0, Teuchos::outArg(len));
  failure.resize(len);
  if (len > 0) Teuchos::broadcast(*comm, 0, len, failure.data());
  CMS_INPUT_CHECK(len > 0, failure);
}

GyroscopicMatrices Substructure::atSpeed(double omega) const {
  if (prototype_) return formed().atSpeed(omega);
  GyroscopicMatrices g;
  g.M = M_;
  g.K = K_;
  const double w2 = omega * omega;
  if (w2 != 0.0 && !K2_.is_null()) g.K = matrixSum(1.0, *K_, w2, *K2_);
  if (!G1_.is_null()) {
    auto G = Teuchos::rcp(new CrsMatrix(*G1_, Teuchos::Copy));
    G->resumeFill();
    G->scale(omega);
    G->fillComplete(G1_->getDomainMap(), G1_->getRangeMap());
    g.G = G;
  } else {
    auto G = Teuchos::rcp(new CrsMatrix(map_, 0));
    G->fillComplete(map_, map_);
    g.G = G;
  }
  return g;
}

}  // namespace cms::substructure
