#include "cms/fem/MatrixSubstructureFile.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cms/core/Error.hpp"

namespace cms::fem {

const char* componentName(Component c) {
  switch (c) {
    case Component::UX: return "ux";
    case Component::UY: return "uy";
    case Component::UZ: return "uz";
    case Component::RX: return "rx";
    case Component::RY: return "ry";
    case Component::RZ: return "rz";
  }
  return "?";
}

long long MatrixSubstructureFile::dofCount() const {
  long long n = 0;
  for (const auto& c : components) n += static_cast<long long>(c.size());
  return n;
}

std::vector<long long> MatrixSubstructureFile::rowOffsets() const {
  std::vector<long long> offsets(nodeIds.size() + 1, 0);
  for (std::size_t i = 0; i < nodeIds.size(); ++i)
    offsets[i + 1] = offsets[i] + static_cast<long long>(i < components.size() ? components[i].size() : 0);
  return offsets;
}

namespace {

const char* const kMagic = "cms-substructure";
const char* const kMatrixNames[] = {"M", "K", "G1", "KT1", "KS1"};  // theory §9

bool knownMatrix(const std::string& name) {
  for (const char* m : kMatrixNames)
    if (name == m) return true;
  return false;
}

/// One record: its tokens and where it is, for messages.
class Record {
public:
  Record(const std::string& path, long long line, std::vector<std::string> tokens)
      : path_(path), line_(line), t_(std::move(tokens)) {}

  const std::string& keyword() const { return t_[0]; }
  std::size_t size() const { return t_.size(); }
  const std::string& operator[](std::size_t i) const { return t_[i]; }
  long long line() const { return line_; }

  [[noreturn]] void fail(std::string what) const {
    // The message quotes the file's bytes: keep it printable and short.
    for (char& c : what)
      if (static_cast<unsigned char>(c) < 32) c = '?';
    if (what.size() > 300) what = what.substr(0, 300) + "...";
    throw InputError(path_ + ":" + std::to_string(line_) + ": " + what);
  }
  void expectSize(std::size_t n, const char* form) const {
    if (t_.size() < n) fail("truncated '" + keyword() + "' record (expected '" + form + "')");
    if (t_.size() > n) fail("unexpected '" + t_[n] + "' after the '" + keyword() + "' record (expected '" + form + "')");
  }
  double number(std::size_t i, const char* what) const {
    const std::string& s = t_[i];
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size()) fail(std::string(what) + " '" + s + "' is not a number");
    if (!std::isfinite(v))  // also overflow: strtod then returns HUGE_VAL
      fail(std::string(what) + " '" + s + "' is not a finite number");
    return v;
  }
  long long integer(std::size_t i, const char* what) const {
    const std::string& s = t_[i];
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || end != s.c_str() + s.size()) fail(std::string(what) + " '" + s + "' is not an integer");
    if (errno == ERANGE) fail(std::string(what) + " '" + s + "' is out of range");
    return v;
  }

private:
  const std::string& path_;
  long long line_;
  std::vector<std::string> t_;
};

std::vector<std::string> tokens(const std::string& line) {
  std::vector<std::string> out;
  const std::string body = line.substr(0, line.find('#'));
  std::size_t i = 0;
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
  while (i < body.size()) {
    while (i < body.size() && space(body[i])) ++i;
    const std::size_t s = i;
    while (i < body.size() && !space(body[i])) ++i;
    if (i > s) out.push_back(body.substr(s, i - s));
  }
  return out;
}

/// A word written into the file must read back as one token.
bool isWord(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c == '#' || std::isspace(static_cast<unsigned char>(c)) || c == '\0') return false;
  return true;
}

}  // namespace

MatrixSubstructureFile readMatrixSubstructureFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  CMS_INPUT_CHECK(!in, path << ": cannot open the file");
  MatrixSubstructureFile f;
  f.path = path;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();

  bool magic = false, units = false, axis = false, origin = false;
  std::map<long long, long long> nodeLine;  // id -> line of its record
  std::map<std::string, long long> matrixLine;
  std::vector<Record> sets;
  std::string line;
  long long lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    Record r(path, lineNo, std::move(t));
    const std::string& key = r.keyword();
    if (!magic) {
      if (key != kMagic) r.fail("expected '" + std::string(kMagic) + " 1' as the first record, found '" + key + "'");
      r.expectSize(2, "cms-substructure <version>");
      const long long version = r.integer(1, "version");
      if (version != 1) r.fail("version " + r[1] + " is not supported (this reader knows version 1)");
      magic = true;
    } else if (key == kMagic) {
      r.fail("second '" + key + "' record");
    } else if (key == "units") {
      r.expectSize(2, "units SI");
      if (units) r.fail("second 'units' record");
      if (r[1] != "SI") r.fail("units '" + r[1] + "' are not supported (only SI)");
      f.units = r[1];
      units = true;
    } else if (key == "matrix") {
      r.expectSize(3, "matrix <name> <path>");
      if (!knownMatrix(r[1])) r.fail("unknown matrix name '" + r[1] + "' (known: M K G1 KT1 KS1)");
      auto [it, fresh] = matrixLine.emplace(r[1], r.line());
      if (!fresh) r.fail("matrix " + r[1] + " is given twice (first on line " + std::to_string(it->second) + ")");
      // A NUL would cut the name short when the file is opened (and in
      // every message naming it).
      for (unsigned char c : r[2])
        if (c < 0x20 || c == 0x7f) r.fail("matrix " + r[1] + ": its file name has a control character (code " + std::to_string(c) + ")");
      const std::filesystem::path p(r[2]);
      f.matrices[r[1]] = p.is_absolute() ? p.string() : (folder / p).string();
    } else if (key == "spin-axis" || key == "spin-origin") {
      r.expectSize(4, key == "spin-axis" ? "spin-axis <x> <y> <z>" : "spin-origin <x> <y> <z>");
      bool& seen = key == "spin-axis" ? axis : origin;
      if (seen) r.fail("second '" + key + "' record");
      seen = true;
      std::array<double, 3>& v = key == "spin-axis" ? f.spinAxis : f.spinOrigin;
      for (int c = 0; c < 3; ++c) v[c] = r.number(1 + c, key == "spin-axis" ? "spin-axis component" : "spin-origin component");
      if (key == "spin-axis") {
        if (v[0] == 0 && v[1] == 0 && v[2] == 0) r.fail("spin-axis is the zero vector");
        f.hasSpinAxis = true;
      }
    } else if (key == "node") {
      if (r.size() < 5) r.fail("truncated 'node' record (expected 'node <id> <x> <y> <z> <components...>')");
      const long long id = r.integer(1, "node id");
      auto [it, fresh] = nodeLine.emplace(id, r.line());
      if (!fresh) r.fail("node " + r[1] + " is given twice (first on line " + std::to_string(it->second) + ")");
      f.nodeIds.push_back(id);
      for (int c = 0; c < 3; ++c) f.coordinates.push_back(r.number(2 + c, "coordinate"));
      std::vector<Component> comps;
      for (std::size_t i = 5; i < r.size(); ++i) {
        Component c;
        if (!parseComponent(r[i], c))
          r.fail("unknown component '" + r[i] + "' of node " + r[1] + " (known: ux uy uz rx ry rz)");
        for (Component d : comps)
          if (d == c) r.fail("component " + r[i] + " of node " + r[1] + " is given twice");
        comps.push_back(c);
      }
      f.components.push_back(std::move(comps));
    } else if (key == "set") {
      if (r.size() < 2) r.fail("truncated 'set' record (expected 'set <name> <node ids...>')");
      if (r.size() < 3) r.fail("set " + r[1] + " names no nodes");
      if (f.nodeSets.count(r[1])) r.fail("set " + r[1] + " is given twice");
      std::vector<long long>& ids = f.nodeSets[r[1]];
      for (std::size_t i = 2; i < r.size(); ++i) ids.push_back(r.integer(i, "node id"));
      sets.push_back(r);
    } else {
      r.fail("unknown record '" + key + "' (known: units matrix spin-axis spin-origin node set)");
    }
  }
  CMS_INPUT_CHECK(in.bad(), path << ": cannot read the file");
  CMS_INPUT_CHECK(!magic, path << ": empty file (expected the record 'cms-substructure 1')");
  CMS_INPUT_CHECK(f.nodeIds.empty(), path << ": no 'node' records");
  CMS_INPUT_CHECK(f.dofCount() == 0, path << ": no node has a DOF component, so there are no matrix rows");
  CMS_INPUT_CHECK(!f.matrices.count("K"), path << ": no stiffness matrix (a 'matrix K <path>' record)");
  CMS_INPUT_CHECK(!f.matrices.count("M"), path << ": no mass matrix (a 'matrix M <path>' record)");
  // Sets may come before the nodes they name; checked once all are read.
  for (const Record& r : sets) {
    std::set<long long> seen;
    for (std::size_t i = 2; i < r.size(); ++i) {
      const long long id = r.integer(i, "node id");
      if (!nodeLine.count(id)) r.fail("set " + r[1] + " names node " + r[i] + ", which has no 'node' record");
      if (!seen.insert(id).second) r.fail("set " + r[1] + " names node " + r[i] + " twice");
    }
  }
  return f;
}

void writeMatrixSubstructureFile(const MatrixSubstructureFile& file, const std::string& path) {
  auto check = [&](bool bad, const std::string& why) {
    if (bad) throw InputError(path + ": cannot write the substructure file: " + why);
  };
  check(file.units != "SI", "units '" + file.units + "' (only SI)");
  check(file.components.size() != file.nodeIds.size() || file.coordinates.size() != 3 * file.nodeIds.size(),
        "node ids, coordinates and components have inconsistent sizes");
  for (const auto& [name, p] : file.matrices) {
    check(!knownMatrix(name), "unknown matrix name '" + name + "'");
    check(!isWord(p), "matrix " + name + " path '" + p + "' is empty or contains whitespace or '#'");
  }
  for (const auto& [name, ids] : file.nodeSets) check(!isWord(name), "set name '" + name + "' is empty or contains whitespace or '#'");
  auto finite = [](const auto& v) {
    for (double x : v)
      if (!std::isfinite(x)) return false;
    return true;
  };
  check(!finite(file.coordinates) || !finite(file.spinAxis) || !finite(file.spinOrigin), "a non-finite number");

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  check(!out, "cannot open it for writing");
  char buf[64];
  auto num = [&](double x) {
    std::snprintf(buf, sizeof buf, "%.17g", x);  // round-trips exactly through strtod
    return std::string(buf);
  };
  out << kMagic << " 1\n";
  out << "units " << file.units << "\n";
  for (const auto& [name, p] : file.matrices) out << "matrix " << name << " " << p << "\n";
  if (file.hasSpinAxis)
    out << "spin-axis " << num(file.spinAxis[0]) << " " << num(file.spinAxis[1]) << " " << num(file.spinAxis[2])
        << "\n";
  if (file.hasSpinAxis || file.spinOrigin != std::array<double, 3>{0, 0, 0})
    out << "spin-origin " << num(file.spinOrigin[0]) << " " << num(file.spinOrigin[1]) << " "
        << num(file.spinOrigin[2]) << "\n";
  for (std::size_t i = 0; i < file.nodeIds.size(); ++i) {
    out << "node " << file.nodeIds[i];
    for (int c = 0; c < 3; ++c) out << " " << num(file.coordinates[3 * i + c]);
    for (Component c : file.components[i]) out << " " << componentName(c);
    out << "\n";
  }
  for (const auto& [name, ids] : file.nodeSets) {
    out << "set " << name;
    for (long long id : ids) out << " " << id;
    out << "\n";
  }
  out.close();
  check(!out, "write failed");
}

bool parseComponent(const std::string& s, Component& c) {
  for (int i = 0; i < 6; ++i)
    if (s == componentName(static_cast<Component>(i))) {
      c = static_cast<Component>(i);
      return true;
    }
  return false;
}

}  // namespace cms::fem
