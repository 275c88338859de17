#include "cms/mesh/InpReader.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cms/core/Error.hpp"

namespace cms::mesh {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// Element types and their node order.
//
// A deck numbers an element's nodes in Abaqus's order; a Mesh holds them in
// the project's (Gmsh's, see CellType in Mesh.hpp). Project node k of a cell
// is deck node order[k] (0-based); corners agree, the mid-edge nodes of the
// quadratic cells do not (doc/user-guide.md, "Meshes", has the table):
//   C3D10: Abaqus edges (1,2) (2,3) (3,1) (1,4) (2,4) (3,4); the project's
//          (0,1) (1,2) (0,2) (0,3) (2,3) (1,3): the last two swap.
//   C3D20: Abaqus (1,2) (2,3) (3,4) (4,1) (5,6) (6,7) (7,8) (8,5) (1,5) (2,6)
//          (3,7) (4,8); the project's (0,1) (0,3) (0,4) (1,2) (1,5) (2,3)
//          (2,6) (3,7) (4,5) (4,7) (5,6) (6,7).
//   C3D15: Abaqus (1,2) (2,3) (3,1) (4,5) (5,6) (6,4) (1,4) (2,5) (3,6); the
//          project's (0,1) (0,2) (0,3) (1,2) (1,4) (2,5) (3,4) (3,5) (4,5).
// ---------------------------------------------------------------------------

constexpr int kIdentity[20] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19};
constexpr int kTet10[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
constexpr int kHex20[20] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 16, 9, 17, 10, 18, 19, 12, 15, 13, 14};
constexpr int kWedge15[15] = {0, 1, 2, 3, 4, 5, 6, 8, 12, 7, 13, 14, 9, 11, 10};

struct InpType {
  const char* name;
  CellType type;
  int nodes;
  int dim;
  int gmshType;  ///< Gmsh's number for the shape, for messages that quote it
  const int* order;
};

constexpr InpType kTypes[] = {
    {"C3D4", CellType::Tet4, 4, 3, 4, kIdentity},        {"C3D8", CellType::Hex8, 8, 3, 5, kIdentity},
    {"C3D8R", CellType::Hex8, 8, 3, 5, kIdentity},       {"C3D8I", CellType::Hex8, 8, 3, 5, kIdentity},
    {"C3D10", CellType::Tet10, 10, 3, 11, kTet10},       {"C3D20", CellType::Hex20, 20, 3, 17, kHex20},
    {"C3D20R", CellType::Hex20, 20, 3, 17, kHex20},      {"C3D15", CellType::Wedge15, 15, 3, 18, kWedge15},
    {"B31", CellType::Line2, 2, 1, 1, kIdentity},
};

std::string supportedTypes() {
  std::string s;
  for (const InpType& t : kTypes) s += (s.empty() ? "" : ", ") + std::string(t.name);
  return s;
}

/// Keywords that generate, copy or move nodes or elements, or wrap them in
/// parts and instances: skipping them would misread the mesh, so they are
/// refused.
bool refusedKeyword(const std::string& k) {
  static const char* const refused[] = {"NGEN",     "NFILL",    "NCOPY",        "NMAP",        "ELGEN",
                                        "ELCOPY",   "SYSTEM",   "PART",         "END PART",    "INSTANCE",
                                        "ASSEMBLY", "END INSTANCE", "END ASSEMBLY"};
  return std::any_of(std::begin(refused), std::end(refused), [&](const char* r) { return k == r; });
}

/// Keywords that change the model's stiffness or connectivity between
/// nodes: skipping them (as materials and steps are) would be a different
/// structure, so they are refused (found by a review: a *TIE dropped with a
/// note).
bool constraintKeyword(const std::string& k) {
  static const char* const refused[] = {"TIE",      "EQUATION",  "MPC",      "RIGID BODY", "COUPLING",
                                        "KINEMATIC", "DISTRIBUTING", "DISTRIBUTING COUPLING", "KINEMATIC COUPLING",
                                        "CONTACT PAIR", "GAP", "SPRING", "DASHPOT", "MASS", "ROTARY INERTIA"};
  return std::any_of(std::begin(refused), std::end(refused), [&](const char* r) { return k == r; });
}

constexpr long long kMaxId = 2147483647;  // as CalculiX's and the .msh scan's integer ids
constexpr int kMaxIncludeDepth = 64;

bool space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && space(s[b])) ++b;
  while (e > b && space(s[e - 1])) --e;
  return s.substr(b, e - b);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

/// Upper case, runs of blanks as one space: "*end  step" -> "END STEP".
std::string keywordName(const std::string& s) {
  std::string out;
  for (char c : trim(s)) {
    if (space(c)) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
  }
  return out;
}

/// A field of the deck as a message may quote it: printable, at most 40 characters.
std::string shown(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
  return s.size() > 40 ? out + "..." : out;
}

/// The comma-separated fields of a line, each trimmed (empty ones kept).
std::vector<std::string> fields(const std::string& text) {
  std::vector<std::string> out;
  std::size_t b = 0;
  for (;;) {
    const std::size_t e = text.find(',', b);
    out.push_back(trim(text.substr(b, e == std::string::npos ? std::string::npos : e - b)));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return out;
}

bool endsWithComma(const std::string& text) {
  const std::string t = trim(text);
  return !t.empty() && t.back() == ',';
}

struct Place {
  int file = -1;
  long line = 0;
};

struct Keyword {
  std::string name;  ///< upper case, e.g. "ELEMENT", "END STEP"
  std::vector<std::pair<std::string, std::string>> params;  ///< upper-case key, value as written
  Place at;

  const std::string* get(const char* key) const {
    for (const auto& [k, v] : params)
      if (k == key) return &v;
    return nullptr;
  }
  bool has(const char* key) const { return get(key) != nullptr; }
};

struct Line {
  std::string text;
  Place at;
};

/// Consecutive elements of one *ELEMENT keyword (or its INPUT= file).
struct ElementBlock {
  const InpType* type = nullptr;
  std::vector<long long> ids;
  std::vector<long long> nodeIds;  ///< type->nodes per element, deck order
  std::vector<Place> at;           ///< the (first) line of each element
};

/// One entry of a set definition, resolved once every node and element is known.
struct SetItem {
  enum Kind { Id, Range, Set, NodesOfElements } kind = Id;
  long long a = 0, b = 0, step = 1;  ///< Id: a; Range: a..b by step
  std::string key;                   ///< Set / NodesOfElements: the set's key
  Place at;
};

/// Additions to one set, in deck order: *NSET/*ELSET, *NODE NSET=, *ELEMENT ELSET=.
struct SetDefinition {
  bool nodes = true;
  std::string key;  ///< upper case
  std::string what;  ///< "*NSET NSET=root", for messages
  std::vector<SetItem> items;
  Place at;
};

struct SetName {
  std::string display;  ///< the spelling of the first definition
  Place at;
};

class Deck {
public:
  explicit Deck(std::string path) : top_(std::move(path)) {}

  Mesh read() {
    files_.push_back({top_, Place{}});
    push(0, top_, Place{});
    parse();
    return build();
  }

private:
  struct File {
    std::string path;
    Place includedFrom;  ///< file -1: the deck itself
  };
  struct Open {
    int file = 0;
    std::string bytes;
    std::size_t pos = 0;
    long line = 0;
    std::string key;  ///< canonical path, for cycles
  };

  // -------------------------------------------------------------------------
  // Messages: "file:line: what", and for an included file where it was
  // included from, up to the deck itself.
  // -------------------------------------------------------------------------

  std::string where(Place p) const {
    if (p.file < 0) return top_;
    return files_[p.file].path + (p.line > 0 ? ":" + std::to_string(p.line) : std::string());
  }
  std::string chain(Place p) const {
    std::string s;
    for (int f = p.file; f >= 0 && files_[f].includedFrom.file >= 0; f = files_[f].includedFrom.file)
      s += " (" + files_[f].path + " is included from " + where(files_[f].includedFrom) + ")";
    return s;
  }
  [[noreturn]] void fail(Place p, const std::string& what) const {
    throw InputError(where(p) + ": " + what + chain(p));
  }
  void note(Place p, const std::string& what) { notes_.push_back(where(p) + ": " + what + chain(p)); }

  // -------------------------------------------------------------------------
  // Lines: files read whole, one at a time; *INCLUDE read in place.
  // -------------------------------------------------------------------------

  /// Opens `path` as file index `file`, read from here on (`from`: the
  /// *INCLUDE or INPUT= that names it).
  void push(int file, const std::string& path, Place from) {
    auto cannot = [&](const std::string& why) {
      if (from.file < 0) throw InputError(path + ": " + why);
      fail(from, "cannot read " + path + ": " + why);
    };
    std::error_code ec;
    if (!fs::exists(path, ec)) cannot("it does not exist");
    if (!fs::is_regular_file(path, ec)) cannot("not a regular file");
    const fs::path canonical = fs::weakly_canonical(path, ec);
    const std::string key = ec ? path : canonical.string();
    for (const Open& o : stack_)
      if (o.key == key) {
        std::string cycle;
        for (const Open& s : stack_) cycle += files_[s.file].path + " -> ";
        fail(from, "including " + path + " again makes a cycle (" + cycle + path + ")");
      }
    if (static_cast<int>(stack_.size()) >= kMaxIncludeDepth)
      fail(from, "includes nested deeper than " + std::to_string(kMaxIncludeDepth));
    std::ifstream in(path, std::ios::binary);
    if (!in) cannot("cannot open the file");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in.bad()) cannot("cannot read the file");
    std::string text = bytes.str();
    if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // a UTF-8 byte order mark, not text
    stack_.push_back({file, std::move(text), 0, 0, key});
  }

  /// A file named by INPUT= (of *INCLUDE or of a data keyword); read from
  /// here on. A relative name is taken from the top deck's folder, as
  /// CalculiX and Abaqus take it from the folder they run in (the deck's):
  /// a nested include's name is not relative to the file that names it. Only
  /// where no such file exists is the including file's folder tried (the
  /// reader's earlier rule), with a note.
  void include(const Keyword& kw) {
    const std::string* input = kw.get("INPUT");
    if (!input || input->empty()) fail(kw.at, "*" + kw.name + ": INPUT= names no file");
    fs::path p = *input;
    if (p.is_relative()) {
      const fs::path fromTop = fs::path(top_).parent_path() / p;
      const fs::path fromHere = fs::path(files_[kw.at.file].path).parent_path() / p;
      std::error_code ec;
      p = fromTop;
      if (fromHere != fromTop) {
        const bool top = fs::exists(fromTop, ec), here = fs::exists(fromHere, ec);
        if (!top && here) {
          p = fromHere;
          note(kw.at, "INPUT=" + shown(*input) + " is not in the deck's folder (where CalculiX looks for it); read " +
                          fromHere.string() + ", beside the including file");
        } else if (top && here) {
          note(kw.at, "INPUT=" + shown(*input) + " read from the deck's folder, as CalculiX does: " +
                          fromTop.string() + " (not " + fromHere.string() + ", beside the including file)");
        }
      }
    }
    files_.push_back({p.string(), kw.at});
    push(static_cast<int>(files_.size()) - 1, p.string(), kw.at);
  }

  bool physical(Line& out) {
    while (!stack_.empty()) {
      Open& o = stack_.back();
      if (o.pos >= o.bytes.size()) {
        stack_.pop_back();
        continue;
      }
      std::size_t e = o.bytes.find('\n', o.pos);
      if (e == std::string::npos) e = o.bytes.size();
      out.text.assign(o.bytes, o.pos, e - o.pos);
      o.pos = e + 1;
      out.at = {o.file, ++o.line};
      return true;
    }
    return false;
  }

  static bool isKeyword(const std::string& text) {
    for (char c : text)
      if (!space(c)) return c == '*';
    return false;
  }

  /// The next line that is neither a comment nor blank, a keyword line with
  /// its continuations; *INCLUDE is followed here.
  bool logical(Line& out) {
    for (;;) {
      if (!physical(out)) return false;
      const std::string t = trim(out.text);
      if (t.empty() || t.compare(0, 2, "**") == 0) continue;
      if (t[0] != '*') return true;
      out.text = t;
      Line more;
      // Continuations come from the keyword's own file: at its end, physical()
      // would go on in the including file and read its next line as more
      // parameters (found by a review).
      const std::size_t depth = stack_.size();
      while (endsWithComma(out.text)) {
        if (stack_.size() != depth || stack_.back().pos >= stack_.back().bytes.size())
          fail(out.at, "the keyword line ends with ',' (more parameters to come) at the end of its file");
        if (!physical(more)) break;
        const std::string m = trim(more.text);
        if (m.compare(0, 2, "**") == 0) continue;
        out.text += m;
      }
      const Keyword kw = keyword(out);
      if (kw.name != "INCLUDE") return true;
      include(kw);
    }
  }

  bool next(Line& out) {
    if (peeked_) {
      out = std::move(*peeked_);
      peeked_.reset();
      return true;
    }
    return logical(out);
  }
  bool dataFollows() {
    if (!peeked_) {
      Line l;
      if (!logical(l)) return false;
      peeked_ = std::move(l);
    }
    return !isKeyword(peeked_->text);
  }
  bool nextData(Line& out) { return dataFollows() && next(out); }

  Keyword keyword(const Line& line) const {
    Keyword kw;
    kw.at = line.at;
    const std::string t = trim(line.text).substr(1);
    std::vector<std::string> f = fields(t);
    kw.name = keywordName(f[0]);
    if (kw.name.empty()) fail(line.at, "a keyword line without a keyword: \"" + shown(line.text) + "\"");
    for (std::size_t i = 1; i < f.size(); ++i) {
      if (f[i].empty()) continue;
      const std::size_t eq = f[i].find('=');
      std::string key = keywordName(f[i].substr(0, eq));
      std::string value = eq == std::string::npos ? std::string() : trim(f[i].substr(eq + 1));
      if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
      if (key.empty()) fail(line.at, "*" + kw.name + ": a parameter without a name: \"" + shown(f[i]) + "\"");
      // A name starts with a letter. A keyword line ending in a comma goes on
      // onto the next line, so data (or a keyword) there would otherwise be
      // taken as parameters and ignored, and the keyword's data lost.
      if (!std::isalpha(static_cast<unsigned char>(key[0])))
        fail(line.at, "*" + kw.name + ": \"" + shown(key) + "\" is not a parameter name (a keyword line that ends with "
                      "a comma continues onto the next line, which must hold parameters: remove the comma)");
      if (kw.has(key.c_str())) fail(line.at, "*" + kw.name + ": parameter " + key + " given twice");
      kw.params.emplace_back(std::move(key), std::move(value));
    }
    return kw;
  }

  // -------------------------------------------------------------------------
  // Numbers.
  // -------------------------------------------------------------------------

  /// An integer field; `positive`: an id in 1 .. 2^31 - 1.
  long long integer(const std::string& s, Place at, const std::string& what, bool positive = true) const {
    std::size_t i = 0;
    bool negative = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
    const bool digits = i < s.size() && std::all_of(s.begin() + static_cast<long>(i), s.end(),
                                                    [](char c) { return c >= '0' && c <= '9'; });
    if (!digits)
      fail(at, what + " \"" + shown(s) + "\" is not an integer" + (positive ? " id" : ""));
    long long v = 0;
    for (; i < s.size(); ++i) {
      v = v * 10 + (s[i] - '0');
      if (v > kMaxId) fail(at, what + " " + shown(s) + " is out of range (ids are 1 to 2147483647)");
    }
    if (negative) v = -v;
    if (positive && v < 1) fail(at, what + " " + shown(s) + " is out of range (ids are 1 to 2147483647)");
    return v;
  }

  double real(const std::string& s, Place at, const std::string& what) const {
    std::string t;
    bool digit = false;
    for (std::size_t i = 0; i < s.size(); ++i) {
      char c = s[i];
      if (c == 'd' || c == 'D') c = 'e';  // Fortran's 1.5D+03
      // Fortran's 1.5+03: a sign after a digit or a point is an exponent's
      // (CalculiX reads numbers with Fortran's F edit descriptor).
      if ((c == '+' || c == '-') && i > 0 && ((s[i - 1] >= '0' && s[i - 1] <= '9') || s[i - 1] == '.')) t += 'e';
      t += c;
      digit = digit || (c >= '0' && c <= '9');
    }
    const bool plain = std::all_of(t.begin(), t.end(), [](char c) {
      return (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E';
    });
    if (!digit || !plain) fail(at, what + " \"" + shown(s) + "\" is not a number");
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size()) fail(at, what + " \"" + shown(s) + "\" is not a number");
    if (!std::isfinite(v)) fail(at, what + " " + shown(s) + " is not finite");
    return v;
  }

  // -------------------------------------------------------------------------
  // Keywords.
  // -------------------------------------------------------------------------

  void parse() {
    Line line;
    while (next(line)) {
      if (!isKeyword(line.text)) fail(line.at, "a data line before any keyword: \"" + shown(trim(line.text)) + "\"");
      const Keyword kw = keyword(line);
      if (kw.name == "NODE") nodes(kw);
      else if (kw.name == "ELEMENT") elements(kw);
      else if (kw.name == "NSET") set(kw, true);
      else if (kw.name == "ELSET") set(kw, false);
      else if (constraintKeyword(kw.name))
        fail(kw.at, "*" + kw.name + " is not supported: it joins or constrains nodes or gives them mass, springs or "
                    "dampers, and skipping it would change the structure (merge the nodes in the mesh, or remove it "
                    "where the scene's attachments, supports, point masses or springs replace it)");
      else if (refusedKeyword(kw.name))
        fail(kw.at, "*" + kw.name + " is not supported: it would generate, copy or place nodes or elements that "
                    "this reader does not follow (write the nodes and elements out, e.g. with the solver's "
                    "own preprocessor, and read that deck)");
      else skip(kw);
    }
  }

  /// A keyword that is not mesh: its data lines are passed over.
  void skip(const Keyword& kw) {
    if (kw.name != "HEADING") {
      auto [it, added] = skipped_.emplace(kw.name, std::make_pair(kw.at, 0L));
      ++it->second.second;
    }
    Line l;
    while (nextData(l)) {
    }
  }

  /// Parameters of a mesh keyword other than `known` are noted and ignored.
  /// A flag (a parameter without "=") not known is refused: a misspelt
  /// GENERATE, or a set name on the line after a keyword line that ends
  /// with a comma, would be noted and the data read otherwise (found by a
  /// review: "*NSET, NSET=ROOT," then "R2" lost the set R2).
  void ignoreOthers(const Keyword& kw, std::initializer_list<const char*> known) {
    for (const auto& [key, value] : kw.params) {
      if (std::any_of(known.begin(), known.end(), [&](const char* k) { return key == k; })) continue;
      if (value.empty())
        fail(kw.at, "*" + kw.name + ": \"" + shown(key) + "\" is not a parameter of *" + kw.name +
                        " (a flag this reader knows: " + flags(known) + "; a keyword line that ends with a comma "
                        "continues onto the next line, which must hold parameters: a data line there? remove the "
                        "comma)");
      note(kw.at, "*" + kw.name + ": parameter " + shown(key) + " ignored");
    }
  }
  static std::string flags(std::initializer_list<const char*> known) {
    std::string out;
    for (const char* k : known)
      if (std::string(k) == "GENERATE" || std::string(k) == "UNSORTED" || std::string(k) == "INTERNAL")
        out += (out.empty() ? "" : ", ") + std::string(k);
    return out.empty() ? "none" : out;
  }

  std::string setName(const Keyword& kw, const char* param) const {
    const std::string* v = kw.get(param);
    if (!v || v->empty()) fail(kw.at, "*" + kw.name + ": " + param + "= names no set");
    for (char c : *v)
      if (static_cast<unsigned char>(c) < 32 || c == 127)
        fail(kw.at, "*" + kw.name + ": " + param + "=\"" + shown(*v) + "\" has a control character");
    return *v;
  }

  /// The definition that adds to set `name` (declared here if new).
  SetDefinition& define(bool nodeSet, const std::string& name, const std::string& what, Place at) {
    const std::string key = upper(name);
    auto& names = nodeSet ? nodeSetNames_ : elementSetNames_;
    if (names.emplace(key, SetName{name, at}).second) (nodeSet ? nodeSetOrder_ : elementSetOrder_).push_back(key);
    definitions_.push_back({nodeSet, key, what, {}, at});
    return definitions_.back();
  }

  void nodes(const Keyword& kw) {
    ignoreOthers(kw, {"NSET", "SYSTEM", "INPUT"});
    if (const std::string* system = kw.get("SYSTEM"); system && upper(trim(*system)) != "R")
      fail(kw.at, "*NODE, SYSTEM=" + shown(*system) + ": only rectangular coordinates (SYSTEM=R) are read");
    const std::size_t definition = definitions_.size();
    if (kw.has("NSET")) define(true, setName(kw, "NSET"), "*NODE NSET=" + shown(*kw.get("NSET")), kw.at);
    if (kw.has("INPUT")) include(kw);
    Line l;
    while (nextData(l)) {
      std::vector<std::string> f = fields(l.text);
      while (!f.empty() && f.back().empty()) f.pop_back();
      if (f.empty()) fail(l.at, "an empty *NODE line");
      if (f.size() > 7)
        fail(l.at, "a *NODE line has the id, up to three coordinates and a normal; this one has " +
                       std::to_string(f.size()) + " fields");
      const long long id = integer(f[0], l.at, "node");
      if (f.size() < 2) fail(l.at, "node " + std::to_string(id) + " has no coordinates");
      nodeIds_.push_back(id);
      nodeAt_.push_back(l.at);
      for (std::size_t c = 1; c <= 3; ++c)
        nodeXyz_.push_back(c < f.size() && !f[c].empty()
                               ? real(f[c], l.at, std::string("coordinate ") + "xyz"[c - 1] + " of node " +
                                                      std::to_string(id))
                               : 0.0);
      if (definition < definitions_.size()) definitions_[definition].items.push_back({SetItem::Id, id, 0, 1, {}, l.at});
    }
  }

  void elements(const Keyword& kw) {
    ignoreOthers(kw, {"TYPE", "ELSET", "INPUT"});
    const std::string* typeName = kw.get("TYPE");
    if (!typeName || typeName->empty())
      fail(kw.at, "*ELEMENT needs TYPE= (one of " + supportedTypes() + ")");
    const std::string name = upper(trim(*typeName));
    const InpType* type = nullptr;
    for (const InpType& t : kTypes)
      if (name == t.name) type = &t;
    if (!type)
      fail(kw.at, "element type " + shown(*typeName) + " is not supported (supported: " + supportedTypes() + ")");
    const std::size_t definition = definitions_.size();
    if (kw.has("ELSET")) define(false, setName(kw, "ELSET"), "*ELEMENT ELSET=" + shown(*kw.get("ELSET")), kw.at);
    if (kw.has("INPUT")) include(kw);
    blocks_.emplace_back();
    ElementBlock& block = blocks_.back();
    block.type = type;
    Line l;
    while (nextData(l)) {
      std::vector<std::string> f = fields(l.text);
      // An element's nodes go on onto the next data line while it lacks
      // nodes, whether or not the line ends with a comma: CalculiX reads a
      // C3D20 so (its elements.f), and decks written without the comma exist.
      auto filled = [&f] {
        while (!f.empty() && f.back().empty()) f.pop_back();
        return static_cast<int>(f.size()) - 1;
      };
      Line more;
      int lines = 1;
      while (filled() >= 0 && filled() < type->nodes && nextData(more)) {
        for (std::string& g : fields(more.text)) f.push_back(std::move(g));
        ++lines;
      }
      filled();
      if (f.empty()) fail(l.at, "an empty *ELEMENT line");
      const long long id = integer(f[0], l.at, "element");
      for (std::size_t k = 1; k < f.size(); ++k)
        if (f[k].empty()) fail(l.at, "element " + std::to_string(id) + ": node " + std::to_string(k) + " is empty");
      if (static_cast<int>(f.size()) - 1 != type->nodes)
        fail(l.at, "element " + std::to_string(id) + " has " + std::to_string(f.size() - 1) + " nodes" +
                       (lines > 1 ? " on " + std::to_string(lines) + " lines (a line short of the type's nodes "
                                                                     "goes on onto the next)"
                                  : std::string()) +
                       "; " + type->name + " has " + std::to_string(type->nodes));
      block.ids.push_back(id);
      block.at.push_back(l.at);
      for (std::size_t k = 1; k < f.size(); ++k)
        block.nodeIds.push_back(integer(f[k], l.at, "element " + std::to_string(id) + ": node"));
      if (definition < definitions_.size())
        definitions_[definition].items.push_back({SetItem::Id, id, 0, 1, {}, l.at});
    }
  }

  void set(const Keyword& kw, bool nodeSet) {
    const char* param = nodeSet ? "NSET" : "ELSET";
    ignoreOthers(kw, nodeSet ? std::initializer_list<const char*>{"NSET", "ELSET", "GENERATE", "INPUT", "UNSORTED",
                                                                  "INTERNAL"}
                             : std::initializer_list<const char*>{"ELSET", "GENERATE", "INPUT", "UNSORTED",
                                                                  "INTERNAL"});
    const std::string name = setName(kw, param);
    const bool generate = kw.has("GENERATE");
    // Resolve the names this definition uses before declaring it, so that
    // "*NSET, NSET=a, ELSET=a" means the element set a.
    std::optional<std::string> ofElements;
    if (nodeSet && kw.has("ELSET")) {
      const std::string es = setName(kw, "ELSET");
      if (!elementSetNames_.count(upper(es)))
        fail(kw.at, "*NSET, ELSET=" + shown(es) + ": no element set of that name is defined above");
      ofElements = upper(es);
    }
    SetDefinition& d = define(nodeSet, name, std::string("*") + kw.name + " " + param + "=" + shown(name), kw.at);
    if (ofElements) d.items.push_back({SetItem::NodesOfElements, 0, 0, 1, *ofElements, kw.at});
    if (kw.has("INPUT")) include(kw);
    const auto& names = nodeSet ? nodeSetNames_ : elementSetNames_;
    const char* what = nodeSet ? "node" : "element";
    Line l;
    while (nextData(l)) {
      std::vector<std::string> f = fields(l.text);
      f.erase(std::remove(f.begin(), f.end(), std::string()), f.end());
      if (generate) {
        if (f.size() < 2 || f.size() > 3)
          fail(l.at, d.what + ", GENERATE: a line is first, last[, step]; this one has " + std::to_string(f.size()) +
                         " fields");
        const long long first = integer(f[0], l.at, std::string("GENERATE: first ") + what);
        const long long last = integer(f[1], l.at, std::string("GENERATE: last ") + what);
        const long long step = f.size() == 3 ? integer(f[2], l.at, "GENERATE: step", false) : 1;
        if (step <= 0) fail(l.at, d.what + ", GENERATE: the step is " + std::to_string(step) + "; it must be positive");
        if (first > last)
          fail(l.at, d.what + ", GENERATE: the first id " + std::to_string(first) + " is above the last " +
                         std::to_string(last));
        d.items.push_back({SetItem::Range, first, last, step, {}, l.at});
        continue;
      }
      for (const std::string& g : f) {
        if ((g[0] >= '0' && g[0] <= '9') || g[0] == '+' || g[0] == '-') {
          d.items.push_back({SetItem::Id, integer(g, l.at, std::string(what) + " of " + d.what), 0, 1, {}, l.at});
          continue;
        }
        std::string ref = g;
        if (ref.size() >= 2 && ref.front() == '"' && ref.back() == '"') ref = ref.substr(1, ref.size() - 2);
        if (!names.count(upper(ref)))
          fail(l.at, d.what + ": \"" + shown(g) + "\" is neither a " + what + " id nor a " + what +
                         " set defined above");
        d.items.push_back({SetItem::Set, 0, 0, 1, upper(ref), l.at});
      }
    }
  }

  // -------------------------------------------------------------------------
  // The mesh: nodes by id, elements resolved, sets in deck order.
  // -------------------------------------------------------------------------

  /// Index of `id` in the sorted `ids`, or -1.
  static std::int64_t find(const std::vector<long long>& ids, long long id) {
    const auto it = std::lower_bound(ids.begin(), ids.end(), id);
    return it != ids.end() && *it == id ? static_cast<std::int64_t>(it - ids.begin()) : -1;
  }

  Mesh build() {
    Mesh mesh;
    mesh.source = top_;
    mesh.namesIgnoreCase = true;  // set names as Abaqus and CalculiX read them
    if (nodeIds_.empty()) throw InputError(top_ + ": no nodes (the deck has no *NODE data lines)");

    // Nodes sorted by id (as the Gmsh reader keeps them), each id once.
    std::vector<std::size_t> order(nodeIds_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return nodeIds_[a] < nodeIds_[b]; });
    std::vector<long long> ids(order.size());
    mesh.nodeTags.resize(order.size());
    mesh.coordinates.resize(3 * order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      ids[i] = nodeIds_[order[i]];
      if (i > 0 && ids[i] == ids[i - 1])
        fail(nodeAt_[order[i]], "node " + std::to_string(ids[i]) + " is defined twice (first at " +
                                    where(nodeAt_[order[i - 1]]) + ")");
      mesh.nodeTags[i] = static_cast<std::size_t>(ids[i]);
      for (int c = 0; c < 3; ++c) mesh.coordinates[3 * i + c] = nodeXyz_[3 * order[i] + c];
    }

    // Elements: every id once, every node defined.
    struct Ref {
      long long id;
      std::size_t block, pos;
    };
    std::vector<Ref> elements;
    for (std::size_t b = 0; b < blocks_.size(); ++b)
      for (std::size_t e = 0; e < blocks_[b].ids.size(); ++e) elements.push_back({blocks_[b].ids[e], b, e});
    std::stable_sort(elements.begin(), elements.end(), [](const Ref& a, const Ref& b) { return a.id < b.id; });
    std::vector<long long> elementIds(elements.size());
    for (std::size_t i = 0; i < elements.size(); ++i) {
      elementIds[i] = elements[i].id;
      if (i > 0 && elementIds[i] == elementIds[i - 1])
        fail(blocks_[elements[i].block].at[elements[i].pos],
             "element " + std::to_string(elementIds[i]) + " is defined twice (first at " +
                 where(blocks_[elements[i - 1].block].at[elements[i - 1].pos]) + ")");
    }
    std::vector<std::vector<std::int64_t>> blockNodes(blocks_.size());
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      const ElementBlock& block = blocks_[b];
      const std::size_t npc = static_cast<std::size_t>(block.type->nodes);
      blockNodes[b].resize(block.nodeIds.size());
      for (std::size_t e = 0; e < block.ids.size(); ++e)
        for (std::size_t k = 0; k < npc; ++k) {
          const long long id = block.nodeIds[e * npc + static_cast<std::size_t>(block.type->order[k])];
          const std::int64_t i = find(ids, id);
          if (i < 0)
            fail(block.at[e], "element " + std::to_string(block.ids[e]) + " refers to node " + std::to_string(id) +
                                  ", which is not defined");
          blockNodes[b][e * npc + k] = i;
        }
    }

    // Sets, each definition adding to its set in deck order.
    std::map<std::string, std::vector<std::int64_t>> nodeSets, elementSets;  // node / element (sorted) indices
    // Each definition adds a member once, however often its lines name it
    // (a set named 16 times a line over 10^4 lines, each time 10^6 nodes,
    // once collected 1.6e11 entries before removing duplicates: bad_alloc).
    std::vector<char> nodeMark(ids.size(), 0), elementMark(elementIds.size(), 0);
    std::map<std::string, std::size_t> nodeCompacted, elementCompacted;  // each set's size when last sorted
    for (const SetDefinition& d : definitions_) {
      const std::vector<long long>& known = d.nodes ? ids : elementIds;
      const char* what = d.nodes ? "node" : "element";
      std::vector<char>& mark = d.nodes ? nodeMark : elementMark;
      std::vector<std::int64_t> members;
      const auto add = [&](std::int64_t i) {
        if (!mark[static_cast<std::size_t>(i)]) mark[static_cast<std::size_t>(i)] = 1, members.push_back(i);
      };
      for (const SetItem& item : d.items) {
        switch (item.kind) {
          case SetItem::Id: {
            const std::int64_t i = find(known, item.a);
            if (i < 0) fail(item.at, d.what + ": " + what + " " + std::to_string(item.a) + " is not defined");
            add(i);
            break;
          }
          case SetItem::Range: {
            long long found = 0;
            for (auto it = std::lower_bound(known.begin(), known.end(), item.a); it != known.end() && *it <= item.b; ++it)
              if ((*it - item.a) % item.step == 0) {
                add(it - known.begin());
                ++found;
              }
            const long long range = (item.b - item.a) / item.step + 1;
            if (found == 0)
              fail(item.at, d.what + ", GENERATE " + std::to_string(item.a) + ", " + std::to_string(item.b) + ", " +
                                std::to_string(item.step) + ": no " + what + " of that range is defined");
            if (found < range)
              note(item.at, d.what + ", GENERATE " + std::to_string(item.a) + ", " + std::to_string(item.b) + ", " +
                                std::to_string(item.step) + ": " + std::to_string(range - found) + " of its " +
                                std::to_string(range) + " ids are not defined " + what + "s (left out)");
            break;
          }
          case SetItem::Set: {
            const auto& sets = d.nodes ? nodeSets : elementSets;
            if (const auto s = sets.find(item.key); s != sets.end())
              for (const std::int64_t i : s->second) add(i);
            break;
          }
          case SetItem::NodesOfElements: {
            if (const auto s = elementSets.find(item.key); s != elementSets.end())
              for (std::int64_t g : s->second) {
                const Ref& r = elements[static_cast<std::size_t>(g)];
                const std::size_t npc = static_cast<std::size_t>(blocks_[r.block].type->nodes);
                for (std::size_t k = 0; k < npc; ++k) add(blockNodes[r.block][r.pos * npc + k]);
              }
            break;
          }
        }
      }
      for (const std::int64_t i : members) mark[static_cast<std::size_t>(i)] = 0;
      // Appended, and sorted (duplicates removed) only when it has doubled
      // since: a set defined anew for each of its 8e4 elements was sorted
      // 8e4 times (52 s; found by a review). A set read by a later
      // definition may hold a member twice meanwhile: add() takes it once.
      std::vector<std::int64_t>& target = (d.nodes ? nodeSets : elementSets)[d.key];
      std::size_t& compacted = (d.nodes ? nodeCompacted : elementCompacted)[d.key];
      target.insert(target.end(), members.begin(), members.end());
      if (target.size() > 2 * compacted + 1024) {
        std::sort(target.begin(), target.end());
        target.erase(std::unique(target.begin(), target.end()), target.end());
        compacted = target.size();
      }
    }
    for (auto* sets : {&nodeSets, &elementSets})
      for (auto& [key, target] : *sets) {
        std::sort(target.begin(), target.end());
        target.erase(std::unique(target.begin(), target.end()), target.end());
      }

    // Groups: element sets first (Mesh::group finds an element set before a
    // node set of the same name), then node sets; empty sets left out.
    int tag = 0;
    std::vector<bool> inSet(elements.size(), false);
    for (const std::string& key : elementSetOrder_) {
      const std::vector<std::int64_t>& members = elementSets[key];
      const SetName& name = elementSetNames_.at(key);
      if (members.empty()) {
        note(name.at, "element set " + shown(name.display) + " is empty (left out)");
        continue;
      }
      PhysicalGroup g;
      g.name = name.display;
      g.tag = ++tag;
      std::map<const InpType*, std::size_t> blockOf;
      for (std::int64_t m : members) {
        inSet[static_cast<std::size_t>(m)] = true;
        const Ref& r = elements[static_cast<std::size_t>(m)];
        const InpType* type = blocks_[r.block].type;
        auto [it, added] = blockOf.emplace(type, g.blocks.size());
        if (added) {
          CellBlock cb;
          cb.type = type->type;
          cb.gmshType = type->gmshType;
          cb.nodesPerCell = type->nodes;
          cb.elementName = type->name;
          g.blocks.push_back(std::move(cb));
          g.dim = std::max(g.dim, type->dim);
        }
        CellBlock& cb = g.blocks[it->second];
        const std::size_t npc = static_cast<std::size_t>(type->nodes);
        cb.cellTags.push_back(static_cast<std::size_t>(r.id));
        cb.nodes.insert(cb.nodes.end(), blockNodes[r.block].begin() + static_cast<long>(r.pos * npc),
                        blockNodes[r.block].begin() + static_cast<long>((r.pos + 1) * npc));
      }
      mesh.groups.push_back(std::move(g));
    }
    for (const std::string& key : nodeSetOrder_) {
      const std::vector<std::int64_t>& members = nodeSets[key];
      const SetName& name = nodeSetNames_.at(key);
      if (members.empty()) {
        note(name.at, "node set " + shown(name.display) + " is empty (left out)");
        continue;
      }
      PhysicalGroup g;
      g.name = name.display;
      g.dim = 0;
      g.tag = ++tag;
      CellBlock cb;
      cb.type = CellType::Point1;
      cb.gmshType = 15;
      cb.nodesPerCell = 1;
      cb.nodes = members;
      for (std::int64_t m : members) cb.cellTags.push_back(mesh.nodeTags[static_cast<std::size_t>(m)]);
      g.blocks.push_back(std::move(cb));
      mesh.groups.push_back(std::move(g));
    }
    if (mesh.groups.empty())
      throw InputError(top_ + ": no node or element sets (name the elements with *ELEMENT, ELSET= or *ELSET: a "
                              "scene uses a mesh through its sets)");

    const auto loose = static_cast<std::size_t>(std::count(inSet.begin(), inSet.end(), false));
    if (loose > 0)
      notes_.push_back(top_ + ": " + std::to_string(loose) + " of " + std::to_string(elements.size()) +
                       " elements are in no element set (a scene uses elements through their sets)");
    if (!skipped_.empty()) {
      std::string list;
      for (const auto& [name, first] : skipped_)
        list += (list.empty() ? "" : ", ") + std::string("*") + shown(name) + " (" + where(first.first) +
                (first.second > 1 ? " and " + std::to_string(first.second - 1) + " more" : std::string()) + ")";
      notes_.push_back(top_ + ": skipped, not mesh (the scene gives materials, sections, supports and the "
                              "analysis): " + list);
    }
    mesh.notes = std::move(notes_);
    return mesh;
  }

  std::string top_;
  std::vector<File> files_;
  std::vector<Open> stack_;
  std::optional<Line> peeked_;

  std::vector<long long> nodeIds_;
  std::vector<double> nodeXyz_;
  std::vector<Place> nodeAt_;
  std::vector<ElementBlock> blocks_;
  std::vector<SetDefinition> definitions_;
  std::map<std::string, SetName> nodeSetNames_, elementSetNames_;
  std::vector<std::string> nodeSetOrder_, elementSetOrder_;
  std::map<std::string, std::pair<Place, long>> skipped_;
  std::vector<std::string> notes_;
};

}  // namespace

Mesh readInp(const std::string& path) { return Deck(path).read(); }

}  // namespace cms::mesh
