#include "MshStructureCheck.hpp"

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
#include <vector>

#include "cms/core/Error.hpp"

namespace cms::mesh::detail {

namespace {

// ---------------------------------------------------------------------------
// Pre-validation of .msh files.
//
// Gmsh 4.8's MSH readers trust the file. Fed corrupted copies of valid
// meshes (tests/unit/mesh/MeshReaderFuzzTest.cpp, and the inputs kept in
// tests/data/fuzz/gmsh/regressions/), it allocates from declared counts
// before reading the data (std::bad_alloc under a memory limit, the OOM
// killer without one), indexes arrays with dimensions read from the file,
// looks nodes up by int so a tag above 2^31 crashes it (segfaults, heap
// corruption), reads some ASCII records line by line and others with
// fscanf, leaves its FILE open when it fails part-way (the descriptor
// leaks on every such read), and treats anything that is not a mesh as a
// .geo script. So before a .msh file reaches Gmsh it is walked once here,
// allocating nothing from any count: every count checked against the bytes
// actually left, every tag against what was declared and against int range,
// each ASCII record on its own line with space-separated values, as Gmsh
// writes them. What passes is read by Gmsh exactly as it was scanned. Where
// that keeps the scan simple it is stricter than Gmsh: MSH 2.2 and 4.1 only,
// little-endian binary, no partitioned meshes or post-processing data, MSH
// 2.2 elements with exactly the two standard tags, element types 1..31 (the
// classic Lagrange cells) and the cubic and quartic quadrangles and
// hexahedra (36, 37, 92, 93) of Lagrange-hex meshes, tags in [1, 2^31 - 1]. The cost is one pass over
// the bytes, below Gmsh's own read (0.35 s of 1.2 s for 10^6 nodes, binary).
// Asked to, the walk keeps an MSH 4.1 file's records (MshContent), from
// which MshReader.cpp makes the mesh without Gmsh: only what passed the
// checks is kept, so the reader needs none of its own.
// ---------------------------------------------------------------------------

struct MshType {
  int nodes = 0;
  int dim = -1;
};

// Node count and dimension of Gmsh element types 1..31, 36, 37, 92 and 93,
// as Gmsh 4.8's getElementProperties reports them.
MshType mshType(long long type) {
  switch (type) {
    case 36: return {16, 2};   // Quad16
    case 37: return {25, 2};   // Quad25
    case 92: return {64, 3};   // Hex64
    case 93: return {125, 3};  // Hex125
    default: break;
  }
  static const MshType table[32] = {
      {0, -1}, {2, 1},  {3, 2},  {4, 2},  {4, 3},  {8, 3},  {6, 3},  {5, 3},
      {3, 1},  {6, 2},  {9, 2},  {10, 3}, {27, 3}, {18, 3}, {14, 3}, {1, 0},
      {8, 2},  {20, 3}, {15, 3}, {13, 3}, {9, 2},  {10, 2}, {12, 2}, {15, 2},
      {15, 2}, {21, 2}, {4, 1},  {5, 1},  {6, 1},  {20, 3}, {35, 3}, {56, 3}};
  if (type < 1 || type > 31) return {};
  return table[type];
}

class MshScanner {
public:
  MshScanner(const std::string& path, const std::string& bytes, MshContent* content)
      : path_(path), b_(bytes.data()), n_(bytes.size()), content_(content) {}

  void run() {
    std::string_view first = rawLine(0);
    if (stripCr(first) != "$MeshFormat")
      failAt(0, "not a Gmsh mesh: the first line must be $MeshFormat");
    while (true) {
      skipBlankLines();
      if (pos_ >= n_) break;
      const std::size_t start = pos_;
      std::string_view line = rawLine(pos_);
      if (line.empty() || line[0] != '$')
        failAt(start, "text outside a section: \"" + excerpt(line) + "\"");
      if (line.size() > 250) failAt(start, "section header line too long");
      header_ = std::string(line.substr(1));  // with its '\r', as Gmsh compares it
      name_ = std::string(stripCr(line.substr(1)));
      sectionStart_ = start;
      pos_ = start + line.size();
      if (pos_ < n_) ++pos_;  // the '\n'
      section();
    }
    if (!formatSeen_) failAt(0, "no $MeshFormat section");
    if (keep()) content_->names = names_, content_->captured = true;
  }

private:
  // -- messages --------------------------------------------------------------
  std::size_t lineOf(std::size_t at) const {
    return 1 + static_cast<std::size_t>(std::count(b_, b_ + std::min(at, n_), '\n'));
  }
  [[noreturn]] void failAt(std::size_t at, const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(lineOf(at)) + ": " + what);
  }
  // Line numbers mean little inside binary data: name the section and byte.
  [[noreturn]] void failBinary(std::size_t at, const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(lineOf(sectionStart_)) + ": $" + name_ +
                     " (binary) at byte " + std::to_string(at) + ": " + what);
  }
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    if (binary_ && dataIsBinary_) failBinary(at, what);
    failAt(at, what);
  }
  static std::string excerpt(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
    return s.size() > 40 ? out + "..." : out;
  }

  // -- lines -----------------------------------------------------------------
  std::string_view rawLine(std::size_t at) const {
    const char* end = static_cast<const char*>(std::memchr(b_ + at, '\n', n_ - at));
    return std::string_view(b_ + at, end ? static_cast<std::size_t>(end - (b_ + at)) : n_ - at);
  }
  static std::string_view stripCr(std::string_view s) {
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    return s;
  }
  static bool blank(std::string_view s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
  }
  void skipBlankLines() {
    while (pos_ < n_) {
      std::string_view line = rawLine(pos_);
      if (!blank(line)) return;
      pos_ += line.size() + (pos_ + line.size() < n_ ? 1 : 0);
    }
  }
  // Gmsh skips to the line "$End<header>" (compared with its '\r', if any).
  void expectSectionEnd() {
    skipBlankLines();
    const std::string want = "$End" + header_;
    if (pos_ >= n_) failAt(pos_, "file ends before $End" + name_);
    std::string_view line = rawLine(pos_);
    if (line != want) failAt(pos_, "expected $End" + name_ + ", found \"" + excerpt(line) + "\"");
    pos_ += line.size() + (pos_ + line.size() < n_ ? 1 : 0);
  }
  std::string_view lineToken(std::size_t& at, std::string_view line) const {
    while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
    const std::size_t s = at;
    while (at < line.size() && !std::isspace(static_cast<unsigned char>(line[at]))) ++at;
    return line.substr(s, at - s);
  }

  // Messages are built only on failure: hot loops pass a lambda.
  template <class W>
  static std::string describe(const W& what) {
    if constexpr (std::is_invocable_v<const W&>) return what();
    else return std::string(what);
  }

  // -- ASCII records ---------------------------------------------------------
  // Newer Gmsh reads ASCII data with fscanf (any whitespace separates
  // values), Gmsh 4.8 reads some of it line by line (a tab, or a record
  // split over two lines, fails it part-way). So values are taken as Gmsh
  // writes them: one record per line, separated by spaces.
  bool atLineEnd() const {
    return pos_ >= n_ || b_[pos_] == '\n' || (b_[pos_] == '\r' && (pos_ + 1 == n_ || b_[pos_ + 1] == '\n'));
  }
  template <class W>
  std::string_view token(const W& what) {
    while (pos_ < n_ && b_[pos_] == ' ') ++pos_;
    if (pos_ >= n_) fail(pos_, "file ends inside $" + name_ + " (expected " + describe(what) + ")");
    if (atLineEnd()) fail(pos_, "line ends before " + describe(what));
    const std::size_t s = pos_;
    for (; !atLineEnd() && b_[pos_] != ' '; ++pos_)
      if (static_cast<unsigned char>(b_[pos_]) < 32)
        fail(pos_, "control character " + std::to_string(static_cast<int>(b_[pos_])) + " in " + describe(what) +
                       " (separate values with spaces)");
    if (b_[s] == '$') fail(s, "section $" + name_ + " ends early (expected " + describe(what) + ")");
    tokenStart_ = s;
    return std::string_view(b_ + s, pos_ - s);
  }
  // The end of an ASCII record: nothing but spaces up to the end of its line.
  void eol(const char* after) {
    if (binary_ && dataIsBinary_) return;
    while (pos_ < n_ && b_[pos_] == ' ') ++pos_;
    if (!atLineEnd()) fail(pos_, "unexpected \"" + excerpt(rawLine(pos_)) + "\" after " + after);
    if (pos_ < n_ && b_[pos_] == '\r') ++pos_;
    if (pos_ < n_) ++pos_;
  }
  template <class W>
  long long parseInt(std::string_view t, const W& what, long long lo, long long hi,
                     std::size_t at) const {
    char buf[32];
    if (t.size() >= sizeof buf) fail(at, describe(what) + " \"" + excerpt(t) + "\" is not an integer");
    std::memcpy(buf, t.data(), t.size());
    buf[t.size()] = '\0';
    if (!(std::isdigit(static_cast<unsigned char>(buf[0])) ||
          (buf[0] == '-' && std::isdigit(static_cast<unsigned char>(buf[1])))))
      fail(at, describe(what) + " \"" + excerpt(t) + "\" is not an integer");
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(buf, &end, 10);
    // Compared with the token's length: a NUL byte inside it would stop
    // strtoll early, and fscanf then fails on that byte.
    if (end != buf + t.size()) fail(at, describe(what) + " \"" + excerpt(t) + "\" is not an integer");
    if (errno == ERANGE || v < lo || v > hi)
      fail(at, describe(what) + " is " + std::string(t) + ", out of range [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "]");
    return v;
  }
  template <class W>
  long long readInt(const W& what, long long lo, long long hi) {
    std::string_view t = token(what);
    return parseInt(t, what, lo, hi, tokenStart_);
  }
  template <class W>
  double readDouble(const W& what) {
    std::string_view t = token(what);
    char buf[128];
    if (t.size() >= sizeof buf) fail(tokenStart_, describe(what) + " \"" + excerpt(t) + "\" is not a number");
    std::memcpy(buf, t.data(), t.size());
    buf[t.size()] = '\0';
    char* end = nullptr;
    const double v = std::strtod(buf, &end);
    if (end != buf + t.size()) fail(tokenStart_, describe(what) + " \"" + excerpt(t) + "\" is not a number");
    return v;  // Gmsh's fscanf accepts the same; out-of-range values are checked after reading
  }

  // -- binary (little-endian only; see run()) --------------------------------
  template <class T, class W>
  T bin(const W& what) {
    if (n_ - pos_ < sizeof(T)) fail(pos_, "file ends inside the data (expected " + describe(what) + ")");
    T v;
    std::memcpy(&v, b_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  template <class W>
  long long binInt(const W& what, long long lo, long long hi) {
    const std::size_t at = pos_;
    const long long v = bin<int>(what);
    if (v < lo || v > hi)
      fail(at, describe(what) + " is " + std::to_string(v) + ", out of range [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "]");
    return v;
  }
  // A count of items of at least itemBytes each must fit in what is left.
  template <class W>
  unsigned long long binCount(const W& what, unsigned long long itemBytes) {
    const std::size_t at = pos_;
    const unsigned long long v = bin<std::uint64_t>(what);
    checkFits(at, what, v, itemBytes);
    return v;
  }
  template <class W>
  void checkFits(std::size_t at, const W& what, unsigned long long count,
                 unsigned long long itemBytes) const {
    if (itemBytes > 0 && count > (n_ - pos_) / itemBytes)
      fail(at, describe(what) + " is " + std::to_string(count) + ", more than the " +
                   std::to_string(n_ - pos_) + " bytes left in the file can hold");
  }
  // ASCII counts: each item takes at least two bytes (a digit and a separator).
  template <class W>
  unsigned long long asciiCount(const W& what, unsigned long long tokensPerItem) {
    const long long v = readInt(what, 0, LLONG_MAX);
    if (static_cast<unsigned long long>(v) > (n_ - pos_) / (2 * tokensPerItem))
      fail(tokenStart_, describe(what) + " is " + std::to_string(v) + ", more than the " +
                            std::to_string(n_ - pos_) + " bytes left in the file can hold");
    return static_cast<unsigned long long>(v);
  }
  template <class W>
  unsigned long long count(const W& what, unsigned long long minBytes,
                           unsigned long long tokensPerItem) {
    return binary_ ? binCount(what, minBytes) : asciiCount(what, tokensPerItem);
  }
  template <class W>
  long long integer(const W& what, long long lo, long long hi) {
    return binary_ ? binInt(what, lo, hi) : readInt(what, lo, hi);
  }
  // Node and element tags are size_t in MSH 4.1, but Gmsh 4.8 looks nodes up
  // by int (GModel::getMeshVertexByTag(int)): a tag above INT_MAX turns
  // negative there and crashes it, one of 2^32 + k aliases node k.
  template <class W>
  std::uint64_t tag(const W& what) {
    if (!binary_) return static_cast<std::uint64_t>(readInt(what, 1, INT_MAX));
    const std::size_t at = pos_;
    const std::uint64_t v = bin<std::uint64_t>(what);
    if (v < 1 || v > static_cast<std::uint64_t>(INT_MAX))
      fail(at, describe(what) + " is " + std::to_string(v) + ", out of range [1, " + std::to_string(INT_MAX) + "]");
    return v;
  }
  template <class W>
  double real(const W& what) {
    return binary_ ? bin<double>(what) : readDouble(what);
  }
  /// Records are kept for the reader (an MSH 4.1 file, content asked for).
  bool keep() const { return content_ && version_ == 4; }

  // -- sections --------------------------------------------------------------
  void section() {
    if (!formatSeen_ && name_ != "MeshFormat") failAt(sectionStart_, "$" + name_ + " before $MeshFormat");
    dataIsBinary_ = false;
    if (name_ == "MeshFormat") return meshFormat();
    if (name_ == "PhysicalNames") return physicalNames();
    if (version_ == 4 && name_ == "Entities") return entities4();
    if (name_ == "Nodes") return version_ == 4 ? nodes4() : nodes2();
    if (name_ == "Elements") return version_ == 4 ? elements4() : elements2();
    if (version_ == 4 && name_ == "Periodic") return periodic4();
    // Names Gmsh would dispatch on (it compares prefixes) but that are not
    // supported here: partitions, post-processing data, MSH 1 sections.
    static const char* gmsh4[] = {"MeshFormat", "PhysicalNames", "Entities", "PartitionedEntities",
                                  "Nodes", "Elements", "Periodic", "GhostElements",
                                  "Parametrizations", "NodeData", "ElementData", "ElementNodeData"};
    static const char* gmsh2[] = {"MeshFormat", "PhysicalNames", "NO", "Nodes", "ParametricNodes",
                                  "ELM", "Elements", "InterpolationScheme", "NodeData",
                                  "ElementData", "ElementNodeData"};
    auto dispatched = [&](const char* p) { return name_.compare(0, std::strlen(p), p) == 0; };
    const bool special = version_ == 4 ? std::any_of(std::begin(gmsh4), std::end(gmsh4), dispatched)
                                       : std::any_of(std::begin(gmsh2), std::end(gmsh2), dispatched);
    if (special) failAt(sectionStart_, "section $" + name_ + " is not supported by this reader");
    // Any other section Gmsh skips line by line (fgets, 256 bytes: longer
    // lines would be split, and a split could fake a marker). Newer Gmsh
    // stops at the section's end marker, Gmsh 4.8's MSH 2 reader at the next
    // line starting with '$': the two agree when that line is the marker.
    while (true) {
      if (pos_ >= n_) failAt(sectionStart_, "$" + name_ + " has no $End" + name_);
      std::string_view line = rawLine(pos_);
      if (line.size() > 250) failAt(pos_, "line too long in $" + name_);
      if (!line.empty() && line[0] == '$' && line != "$End" + header_)
        failAt(pos_, "\"" + excerpt(line) + "\" inside $" + name_ + " (expected $End" + name_ + ")");
      pos_ += line.size() + (pos_ + line.size() < n_ ? 1 : 0);
      if (line == "$End" + header_) return;
    }
  }
  void once(bool& seen) {
    if (seen) failAt(sectionStart_, "second $" + name_ + " section");
    seen = true;
  }

  void meshFormat() {
    once(formatSeen_);
    std::string_view line = rawLine(pos_);
    const std::size_t at = pos_;
    std::size_t i = 0;
    const std::string_view v = lineToken(i, line), type = lineToken(i, line), size = lineToken(i, line);
    if (v.empty() || type.empty() || size.empty() || !lineToken(i, line).empty())
      failAt(at, "expected \"<version> <file-type> <data-size>\" after $MeshFormat");
    if (v == "2.2") version_ = 2;
    else if (v == "4.1") version_ = 4;
    else
      failAt(at, "MSH format version " + excerpt(v) + " is not supported (2.2 and 4.1 are)");
    const long long t = parseInt(type, "file-type", 0, 1, at);
    parseInt(size, "data-size", 8, 8, at);
    binary_ = t == 1;
    pos_ = at + line.size() + (at + line.size() < n_ ? 1 : 0);
    if (binary_) {
      dataIsBinary_ = true;
      if (n_ - pos_ < 4) failBinary(pos_, "file ends before the byte-order word");
      const int one = bin<int>("the byte-order word");
      if (one != 1) failBinary(pos_ - 4, "byte-order word is " + std::to_string(one) +
                                         ", not 1 (big-endian files are not supported)");
    }
    expectSectionEnd();
  }

  void physicalNames() {
    once(namesSeen_);
    const long long count = countLine("number of physical names");
    std::map<std::pair<long long, std::string>, long long> byName;
    for (long long k = 0; k < count; ++k) {
      if (pos_ >= n_) failAt(pos_, "file ends inside $PhysicalNames");
      const std::size_t ls = pos_;
      const std::string_view line = rawLine(pos_);
      // Gmsh reads "dim tag" with fscanf and the name with fgets(256).
      if (line.size() > 250) failAt(ls, "physical name line too long");
      std::size_t j = 0;
      const std::string_view d = lineToken(j, line), t = lineToken(j, line);
      if (d.empty() || t.empty()) failAt(ls, "expected <dim> <tag> \"<name>\"");
      const long long dim = parseInt(d, "physical dimension", 0, 3, ls);
      const long long tag = parseInt(t, "physical tag", 1, INT_MAX, ls);
      std::string_view rest = stripCr(line.substr(j));
      while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
      while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t')) rest.remove_suffix(1);
      if (rest.size() < 2 || rest.front() != '"' || rest.back() != '"' ||
          rest.substr(1, rest.size() - 2).find('"') != std::string_view::npos)
        failAt(ls, "expected <dim> <tag> \"<name>\"");
      const std::string name(rest.substr(1, rest.size() - 2));
      // Gmsh handles names as C strings: a NUL would cut one short.
      if (std::any_of(name.begin(), name.end(), [](char c) { return static_cast<unsigned char>(c) < 32; }))
        failAt(ls, "control character in a physical name");
      if (!names_.emplace(std::make_pair(dim, tag), name).second)
        failAt(ls, "physical group " + std::to_string(dim) + ":" + std::to_string(tag) + " named twice");
      // Gmsh silently keeps only the first of two groups sharing a name.
      auto [it, fresh] = byName.emplace(std::make_pair(dim, name), tag);
      if (!fresh && !name.empty())
        failAt(ls, "physical name \"" + name + "\" of dimension " + std::to_string(dim) +
                       " is used twice (tags " + std::to_string(it->second) + " and " +
                       std::to_string(tag) + ")");
      pos_ = ls + line.size() + (ls + line.size() < n_ ? 1 : 0);
    }
    expectSectionEnd();
  }

  void entities4() {
    once(entitiesSeen_);
    if (nodesSeen_) failAt(sectionStart_, "$Entities after $Nodes");
    dataIsBinary_ = binary_;
    unsigned long long num[4];
    for (int d = 0; d < 4; ++d)
      num[d] = count("number of entities of dimension " + std::to_string(d), d == 0 ? 36 : 68,
                     d == 0 ? 5 : 9);
    eol("the entity counts");
    for (int d = 0; d < 4; ++d)
      for (unsigned long long e = 0; e < num[d]; ++e) {
        const std::string what = "entity " + std::to_string(e + 1) + " of dimension " + std::to_string(d);
        const long long t = integer("tag of " + what, 1, INT_MAX);
        if (!entities_.emplace(d, t).second)
          fail(binary_ ? pos_ - 4 : tokenStart_, "entity " + std::to_string(t) + " of dimension " +
                                                     std::to_string(d) + " declared twice");
        for (int k = 0; k < (d == 0 ? 3 : 6); ++k) real("bounding box of " + what);
        const unsigned long long nphys = count("number of physical tags of " + what, 4, 1);
        std::vector<long long>* phys = keep() ? &content_->physicals[{d, t}] : nullptr;
        for (unsigned long long k = 0; k < nphys; ++k) {
          const long long p = integer("physical tag of " + what, 1, INT_MAX);
          if (phys) phys->push_back(p);
        }
        if (d > 0) {
          const unsigned long long nb = count("number of bounding entities of " + what, 4, 1);
          for (unsigned long long k = 0; k < nb; ++k)
            integer("bounding entity of " + what, -INT_MAX, INT_MAX);
        }
        eol("an entity");
      }
    expectSectionEnd();
  }

  /// The header line of a 4.1 $Nodes or $Elements section: its block count,
  /// its `item` count (each item at least `bytes` binary bytes or `chars`
  /// ASCII characters of what follows), the smallest and largest tags.
  std::pair<unsigned long long, unsigned long long> sectionCounts(const std::string& item, int bytes, int chars) {
    const unsigned long long blocks = count("number of " + item + " blocks", 20, 4);
    const unsigned long long total = count("number of " + item + "s", bytes, chars);
    for (const char* which : {"minimum ", "maximum "}) {
      if (binary_) bin<std::uint64_t>(which + item + " tag");
      else readInt(which + item + " tag", 0, LLONG_MAX);
    }
    const std::string counts = "the " + item + " counts";
    eol(counts.c_str());
    return {blocks, total};
  }

  void nodes4() {
    once(nodesSeen_);
    dataIsBinary_ = binary_;
    const auto [blocks, total] = sectionCounts("node", 32, 4);
    unsigned long long seen = 0;
    for (unsigned long long k = 0; k < blocks; ++k) {
      const std::string what = "node block " + std::to_string(k + 1);
      const long long dim = integer("entity dimension of " + what, 0, 3);
      const long long etag = integer("entity tag of " + what, 1, INT_MAX);
      const long long parametric = integer("parametric flag of " + what, 0, 1);
      const int n = 3 + (parametric ? static_cast<int>(dim) : 0);
      const unsigned long long nn = count("number of nodes in " + what, 8 + 8 * n, 1 + n);
      eol("a node block header");
      // Gmsh creates a discrete entity for a block whose entity is undeclared.
      entities_.emplace(static_cast<int>(dim), etag);
      if (nn > total - seen)
        fail(binary_ ? pos_ - 8 : tokenStart_, what + " goes past the " + std::to_string(total) +
                                                   " nodes declared in the section header");
      seen += nn;
      const std::size_t first = nodeTags_.size();
      for (unsigned long long j = 0; j < nn; ++j) {
        nodeTags_.push_back(tag([&] { return "node tag in " + what; }));
        eol("a node tag");
      }
      for (unsigned long long j = 0; j < nn; ++j) {
        for (int c = 0; c < n; ++c) {
          const double x =
              real([&] { return "coordinate " + std::to_string(c + 1) + " of node " + std::to_string(nodeTags_[first + j]); });
          if (c < 3 && keep()) content_->coordinates.push_back(x);
        }
        eol("node coordinates");
      }
    }
    if (seen != total)
      fail(pos_, "the node blocks hold " + std::to_string(seen) + " nodes, the header declares " +
                     std::to_string(total));
    finishNodes();
    if (keep()) content_->nodeTags = nodeTags_;
    expectSectionEnd();
  }

  void nodes2() {
    once(nodesSeen_);
    const long long num = countLine("number of nodes");
    dataIsBinary_ = binary_;
    if (binary_) checkFits(pos_, "number of nodes", static_cast<unsigned long long>(num), 28);
    for (long long k = 0; k < num; ++k) {
      nodeTags_.push_back(static_cast<std::uint64_t>(integer("node tag", 1, INT_MAX)));
      for (int c = 0; c < 3; ++c)
        real([&] { return "coordinate " + std::to_string(c + 1) + " of node " + std::to_string(nodeTags_.back()); });
      eol("a node");
    }
    finishNodes();
    expectSectionEnd();
  }

  // MSH 2 counts are read with fgets + sscanf: alone on their line.
  long long countLine(const std::string& what) {
    const std::size_t at = pos_;
    std::string_view line = rawLine(pos_);
    std::size_t i = 0;
    const std::string_view c = lineToken(i, line);
    if (c.empty() || !lineToken(i, line).empty()) failAt(at, "expected the " + what + " alone on its line");
    const long long v = parseInt(c, what, 0, INT_MAX, at);
    pos_ = at + line.size() + (at + line.size() < n_ ? 1 : 0);
    if (static_cast<unsigned long long>(v) > (n_ - pos_) / 2)
      failAt(at, what + " is " + std::to_string(v) + ", more than the " + std::to_string(n_ - pos_) +
                     " bytes left in the file can hold");
    return v;
  }

  void finishNodes() {
    sortedNodes_ = nodeTags_;
    std::sort(sortedNodes_.begin(), sortedNodes_.end());
    auto dup = std::adjacent_find(sortedNodes_.begin(), sortedNodes_.end());
    if (dup != sortedNodes_.end())
      failAt(sectionStart_, "node tag " + std::to_string(*dup) + " appears twice in $Nodes");
  }
  void nodeRef(std::uint64_t node, std::uint64_t element, std::size_t at) {
    if (!std::binary_search(sortedNodes_.begin(), sortedNodes_.end(), node))
      fail(at, "element " + std::to_string(element) + " refers to node " + std::to_string(node) +
                   ", which is not in $Nodes");
  }

  void elements4() {
    once(elementsSeen_);
    if (!nodesSeen_) failAt(sectionStart_, "$Elements before $Nodes");
    dataIsBinary_ = binary_;
    const auto [blocks, total] = sectionCounts("element", 16, 2);
    unsigned long long seen = 0;
    for (unsigned long long k = 0; k < blocks; ++k) {
      const std::string what = "element block " + std::to_string(k + 1);
      const long long dim = integer("entity dimension of " + what, 0, 3);
      const long long etag = integer("entity tag of " + what, 1, INT_MAX);
      const std::size_t typeAt = binary_ ? pos_ : 0;
      const long long type = integer("element type of " + what, INT_MIN, INT_MAX);
      const std::size_t at = binary_ ? typeAt : tokenStart_;
      const MshType info = mshType(type);
      if (info.nodes == 0) fail(at, "element type " + std::to_string(type) + " in " + what + " is not supported");
      if (info.dim != dim)
        fail(at, "element type " + std::to_string(type) + " (dimension " + std::to_string(info.dim) +
                     ") in " + what + " on an entity of dimension " + std::to_string(dim));
      if (!entities_.count({static_cast<int>(dim), etag}))
        fail(at, what + " is on entity " + std::to_string(etag) + " of dimension " + std::to_string(dim) +
                     ", which is not declared");
      const unsigned long long ne = count("number of elements in " + what, 8ull * (1 + info.nodes), 1 + info.nodes);
      eol("an element block header");
      MshContent::Block* block = nullptr;
      if (keep()) {
        content_->blocks.push_back({static_cast<int>(dim), etag, static_cast<int>(type), info.nodes, {}, {}});
        block = &content_->blocks.back();
      }
      cellNodes_ = block ? &block->nodes : nullptr;
      if (ne > total - seen)
        fail(binary_ ? pos_ - 8 : tokenStart_, what + " goes past the " + std::to_string(total) +
                                                   " elements declared in the section header");
      seen += ne;
      for (unsigned long long j = 0; j < ne; ++j) {
        const std::uint64_t e = tag([&] { return "element tag in " + what; });
        elementTags_.push_back(e);
        if (block) block->cellTags.push_back(e);
        if (binary_) {
          for (int c = 0; c < info.nodes; ++c) {
            const std::size_t nat = pos_;
            const std::uint64_t node = tag([&] { return "node tag of element " + std::to_string(e); });
            nodeRef(node, e, nat);
            if (block) block->nodes.push_back(node);
          }
        } else {
          elementLine4(e, info.nodes);
        }
      }
    }
    if (seen != total)
      fail(pos_, "the element blocks hold " + std::to_string(seen) + " elements, the header declares " +
                     std::to_string(total));
    finishElements();
    expectSectionEnd();
  }

  // Gmsh 4.8 reads an element's node tags from the rest of its tag's line
  // (fgets into 10000 bytes, then sscanf "%lu %[0-9- ]"): space-separated
  // digits only, all on that line.
  void elementLine4(std::uint64_t element, int nodes) {
    const std::size_t at = pos_;
    std::string_view line = stripCr(rawLine(pos_));
    if (line.size() > 9000) failAt(at, "line of element " + std::to_string(element) + " too long");
    std::size_t i = 0;
    int found = 0;
    while (true) {
      while (i < line.size() && line[i] == ' ') ++i;
      if (i == line.size()) break;
      const std::size_t s = i;
      while (i < line.size() && line[i] != ' ') ++i;
      const std::string_view t = line.substr(s, i - s);
      if (!std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
        failAt(at + s, "node tag \"" + excerpt(t) + "\" of element " + std::to_string(element) +
                           " is not a positive integer (node tags separated by spaces on the element's line)");
      if (++found > nodes)
        failAt(at, "element " + std::to_string(element) + " has more than " + std::to_string(nodes) + " nodes");
      const auto node = static_cast<std::uint64_t>(parseInt(t, "node tag", 1, INT_MAX, at + s));
      nodeRef(node, element, at + s);
      if (cellNodes_) cellNodes_->push_back(node);
    }
    if (found != nodes)
      failAt(at, "element " + std::to_string(element) + " has " + std::to_string(found) +
                     " node tags on its line, its type needs " + std::to_string(nodes));
    pos_ = at + rawLine(at).size() + (at + rawLine(at).size() < n_ ? 1 : 0);
  }

  void elements2() {
    once(elementsSeen_);
    if (!nodesSeen_) failAt(sectionStart_, "$Elements before $Nodes");
    const long long num = countLine("number of elements");
    dataIsBinary_ = binary_;
    long long seen = 0;
    while (seen < num) {
      if (binary_) {
        const std::size_t at = pos_;
        const long long type = binInt("element type", INT_MIN, INT_MAX);
        const MshType info = mshType(type);
        if (info.nodes == 0) failBinary(at, "element type " + std::to_string(type) + " is not supported");
        const long long ne = binInt("number of elements of the block", 1, num - seen);
        binInt("number of tags (must be 2: physical, elementary)", 2, 2);
        checkFits(at, "number of elements", static_cast<unsigned long long>(ne), 4ull * (3 + info.nodes));
        for (long long j = 0; j < ne; ++j) element2(info);
        seen += ne;
      } else {
        element2(MshType{});
        ++seen;
      }
    }
    finishElements();
    expectSectionEnd();
  }

  // One MSH 2 element; ASCII records carry their type, binary ones not.
  void element2(MshType info) {
    const std::uint64_t e = static_cast<std::uint64_t>(integer("element tag", 1, INT_MAX));
    auto of = [&](const char* what) { return [what, e] { return what + (" of element " + std::to_string(e)); }; };
    if (!binary_) {
      const long long type = readInt(of("element type"), INT_MIN, INT_MAX);
      info = mshType(type);
      if (info.nodes == 0)
        fail(tokenStart_, "element type " + std::to_string(type) + " of element " + std::to_string(e) +
                              " is not supported");
      readInt(of("number of tags (must be 2: physical, elementary)"), 2, 2);
    }
    integer(of("physical tag"), 0, INT_MAX);
    integer(of("elementary tag"), 1, INT_MAX);
    elementTags_.push_back(e);
    for (int c = 0; c < info.nodes; ++c) {
      const std::size_t at = pos_;
      const long long node = integer(of("node tag"), 1, INT_MAX);
      nodeRef(static_cast<std::uint64_t>(node), e, binary_ ? at : tokenStart_);
    }
    eol("an element");
  }

  void finishElements() {
    std::sort(elementTags_.begin(), elementTags_.end());
    auto dup = std::adjacent_find(elementTags_.begin(), elementTags_.end());
    if (dup != elementTags_.end())
      failAt(sectionStart_, "element tag " + std::to_string(*dup) + " appears twice in $Elements");
  }

  void periodic4() {
    once(periodicSeen_);
    if (!nodesSeen_) failAt(sectionStart_, "$Periodic before $Nodes");
    dataIsBinary_ = binary_;
    const unsigned long long links = count("number of periodic links", 36, 5);
    eol("the number of periodic links");
    for (unsigned long long k = 0; k < links; ++k) {
      const std::string what = "periodic link " + std::to_string(k + 1);
      const std::size_t at = pos_;
      const long long dim = integer("entity dimension of " + what, 0, 2);
      const long long slave = integer("entity tag of " + what, 1, INT_MAX);
      const long long master = integer("source entity tag of " + what, 1, INT_MAX);
      eol("the entities of a periodic link");
      // Gmsh skips the rest of a link whose entities it does not know, and
      // would then read its data as the next link.
      for (long long t : {slave, master})
        if (!entities_.count({static_cast<int>(dim), t}))
          fail(binary_ ? at : tokenStart_, what + " names entity " + std::to_string(t) + " of dimension " +
                                               std::to_string(dim) + ", which is not declared");
      const unsigned long long affine = count("number of affine coefficients of " + what, 8, 1);
      if (affine != 0 && affine != 16)
        fail(binary_ ? pos_ - 8 : tokenStart_, what + " has " + std::to_string(affine) +
                                                   " affine coefficients (0 or 16)");
      for (unsigned long long j = 0; j < affine; ++j) real("affine coefficient of " + what);
      eol("the affine transformation");
      const unsigned long long pairs = count("number of node pairs of " + what, 16, 2);
      eol("the number of node pairs");
      for (unsigned long long j = 0; j < pairs; ++j) {
        for (int k = 0; k < 2; ++k) {
          const std::size_t nat = binary_ ? pos_ : 0;
          const std::uint64_t node = tag([&] { return "node tag in " + what; });
          if (!std::binary_search(sortedNodes_.begin(), sortedNodes_.end(), node))
            fail(binary_ ? nat : tokenStart_, what + " names node " + std::to_string(node) + ", which is not in $Nodes");
        }
        eol("a node pair");
      }
    }
    expectSectionEnd();
  }

  const std::string& path_;
  const char* b_;
  std::size_t n_;
  std::size_t pos_ = 0, tokenStart_ = 0, sectionStart_ = 0;
  std::string header_, name_;
  int version_ = 0;
  bool binary_ = false, dataIsBinary_ = false;
  bool formatSeen_ = false, namesSeen_ = false, entitiesSeen_ = false, nodesSeen_ = false,
       elementsSeen_ = false, periodicSeen_ = false;
  std::set<std::pair<int, long long>> entities_;
  std::map<std::pair<long long, long long>, std::string> names_;
  std::vector<std::uint64_t> nodeTags_, sortedNodes_, elementTags_;
  MshContent* content_ = nullptr;
  std::vector<std::uint64_t>* cellNodes_ = nullptr;  ///< the kept block's node tags, while its cells are read
};

}  // namespace

void checkMshStructure(const std::string& path, const std::string& bytes, MshContent* content) {
  if (content) *content = MshContent{};
  MshScanner(path, bytes, content).run();
}

}  // namespace cms::mesh::detail
