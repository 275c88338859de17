// A scene's YAML read by yaml-cpp (a complete YAML 1.2 parser: block and
// flow sequences, multi-line flow mappings, anchors) into the Teuchos
// ParameterList that Scene::fromParameters checks key by key (issue 17).
// Types as Teuchos' own YAML reader gives them, so that the checks and their
// messages are unchanged: a plain integer is an int, another number a
// double, true/false a bool, anything else (and every quoted scalar) a
// string; a sequence of numbers an Array<int> (all integers) or
// Array<double>, of other scalars an Array<string>; a mapping a sublist.
#include "YamlScene.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <limits>
#include <map>
#include <regex>
#include <sstream>

#include <Teuchos_Array.hpp>
#include <yaml-cpp/yaml.h>

#include "cms/core/Error.hpp"

namespace cms::scene::detail {

namespace {

const std::regex kInteger(R"([-+]?[0-9]+)");
const std::regex kReal(R"([-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?|[-+]?\.(inf|Inf|INF)|\.(nan|NaN|NAN))");

std::string where(const std::string& path, const YAML::Node& n) {
  const auto m = n.Mark();
  return path + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

bool plain(const YAML::Node& n) { return n.Tag() != "!"; }  // quoted scalars carry the "!" tag

bool isInteger(const YAML::Node& n) {
  if (!plain(n) || !std::regex_match(n.Scalar(), kInteger)) return false;
  errno = 0;
  const long long v = std::strtoll(n.Scalar().c_str(), nullptr, 10);
  return errno == 0 && v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max();
}

bool isReal(const YAML::Node& n) { return plain(n) && std::regex_match(n.Scalar(), kReal); }

double real(const YAML::Node& n) {
  const std::string& s = n.Scalar();
  if (s.find("inf") != std::string::npos || s.find("Inf") != std::string::npos || s.find("INF") != std::string::npos)
    return s[0] == '-' ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  if (s.find("nan") != std::string::npos || s.find("NaN") != std::string::npos || s.find("NAN") != std::string::npos)
    return std::numeric_limits<double>::quiet_NaN();
  return std::strtod(s.c_str(), nullptr);
}

void fill(Teuchos::ParameterList& list, const YAML::Node& map, const std::string& path);

void setValue(Teuchos::ParameterList& list, const std::string& key, const YAML::Node& v, const std::string& path) {
  switch (v.Type()) {
    case YAML::NodeType::Map:
      fill(list.sublist(key), v, path);
      return;
    case YAML::NodeType::Null:
      list.set(key, std::string());
      return;
    case YAML::NodeType::Scalar: {
      const std::string& s = v.Scalar();
      if (isInteger(v)) list.set(key, std::atoi(s.c_str()));
      else if (isReal(v)) list.set(key, real(v));
      else if (plain(v) && (s == "true" || s == "True" || s == "TRUE")) list.set(key, true);
      else if (plain(v) && (s == "false" || s == "False" || s == "FALSE")) list.set(key, false);
      else list.set(key, s);
      return;
    }
    case YAML::NodeType::Sequence: {
      bool ints = true, reals = true;
      for (const auto& item : v) {
        CMS_INPUT_CHECK(!item.IsScalar(), where(path, item) << ": not a valid scene file (key '" << key
                                                            << "': a list holds numbers or names, not lists or mappings)");
        ints = ints && isInteger(item);
        reals = reals && (isInteger(item) || isReal(item));
      }
      if (v.size() > 0 && ints) {
        Teuchos::Array<int> a;
        for (const auto& item : v) a.push_back(std::atoi(item.Scalar().c_str()));
        list.set(key, a);
      } else if (v.size() > 0 && reals) {
        Teuchos::Array<double> a;
        for (const auto& item : v) a.push_back(real(item));
        list.set(key, a);
      } else {
        Teuchos::Array<std::string> a;
        for (const auto& item : v) a.push_back(item.Scalar());
        list.set(key, a);
      }
      return;
    }
    default:
      CMS_INPUT_CHECK(true, where(path, v) << ": not a valid scene file (key '" << key << "' has no value)");
  }
}

void fill(Teuchos::ParameterList& list, const YAML::Node& map, const std::string& path) {
  // yaml-cpp keeps a repeated key, and setting it again here would keep the
  // last silently: the line scan before the parse (Scene.cpp) does not follow
  // flow mappings ({Vectors: 10, Vectors: 2}) or a file after a tab, so every
  // mapping is checked here too.
  std::map<std::string, int> seen;  // key -> line
  for (const auto& kv : map) {
    CMS_INPUT_CHECK(!kv.first.IsScalar(), where(path, kv.first) << ": not a valid scene file (a key must be a name)");
    const auto [at, fresh] = seen.emplace(kv.first.Scalar(), kv.first.Mark().line + 1);
    CMS_INPUT_CHECK(!fresh, where(path, kv.first) << ": duplicate key '" << kv.first.Scalar() << "' (first at line "
                                                  << at->second << ")");
    setValue(list, kv.first.Scalar(), kv.second, path);
  }
}

/// yaml-cpp 0.7 (Debian 12) never returns from a document whose first token
/// is ',' (", x" after any blank or comment lines, directives or "---"): it
/// allocates nodes until killed. The scene fuzz test found it (a comment
/// line that lost its '#'). Such a document is not YAML (',' cannot begin a
/// plain scalar): refused here, with its line, before the parser sees it.
/// The same happens where a ',' begins a line at or left of the root node's
/// column, after a root sequence or an indented root mapping ("  x: 1" then
/// ", y"; the long fuzz run). Outside a flow collection, a block scalar or a
/// plain scalar's continuation (all indented past the root) a ',' cannot
/// begin a line there either: refused too.
void refuseLeadingComma(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  bool documentStart = true;
  int line = 0;
  int rootIndent = -1;          // the document's root node's column (-1: none yet)
  bool rootScalar = false;      // a root block scalar ("--- |"): its content may start at column 0
  int flow = 0;                 // open [ and { on the lines so far
  int blockParent = -1;         // a block scalar's parent column: lines indented past it are content
  const auto refuse = [&](std::size_t i, const char* why) {
    CMS_INPUT_CHECK(true, path << ":" << line << ":" << i + 1 << ": not a valid scene file (" << why << ")");
  };
  for (std::string l; std::getline(in, l);) {
    ++line;
    if (!l.empty() && l.back() == '\r') l.pop_back();                          // CRLF
    if (line == 1 && l.compare(0, 3, "\xEF\xBB\xBF") == 0) l.erase(0, 3);  // a byte-order mark
    std::size_t i = l.find_first_not_of(" \t");
    if (i == std::string::npos) continue;
    if (blockParent >= 0) {
      if (static_cast<int>(i) > blockParent) continue;  // block scalar content
      blockParent = -1;
    }
    if (l[i] == '#' || (i == 0 && l[0] == '%')) continue;
    // Document markers only in column 0 (indented, they are content of a
    // block scalar: found by a review).
    if (i == 0 && (l.compare(0, 3, "---") == 0 || l.compare(0, 3, "...") == 0) &&
        (l.size() == 3 || l[3] == ' ' || l[3] == '\t')) {
      documentStart = true, rootIndent = -1, rootScalar = false, flow = 0;
      i = l.find_first_not_of(" \t", 3);
      if (i == std::string::npos || l[i] == '#') continue;
    }
    if (documentStart) {
      // A node's properties (an anchor &a, a tag !t) may come first, on this
      // line or alone on earlier ones.
      while (i < l.size() && (l[i] == '&' || l[i] == '!')) {
        i = l.find_first_of(" \t", i);
        if (i != std::string::npos) i = l.find_first_not_of(" \t", i);
        if (i == std::string::npos) break;
      }
      if (i == std::string::npos || l[i] == '#') continue;  // properties alone: the node is on a later line
      if (l[i] == ',') refuse(i, "a document cannot begin with ','");
      documentStart = false;
      rootIndent = static_cast<int>(l.compare(0, 3, "---") == 0 ? 0 : i);
      rootScalar = l[i] == '|' || l[i] == '>';
    } else if (l[i] == ',' && flow == 0 && !rootScalar && static_cast<int>(i) <= rootIndent) {
      refuse(i, "a ',' at the start of a line there begins no node: a comment line that lost its '#'?");
    }
    // Brackets outside quotes and comments; a block scalar's header ("key: |",
    // "- >-") makes the more indented lines after it content.
    char quote = 0;
    std::size_t last = std::string::npos;
    for (std::size_t k = i; k < l.size(); ++k) {
      const char c = l[k];
      if (quote) {
        if (c == quote) quote = 0;
        continue;
      }
      if (c == '\'' || c == '"') quote = c;
      else if (c == '#' && (k == 0 || l[k - 1] == ' ' || l[k - 1] == '\t')) break;
      else if (c == '[' || c == '{') ++flow;
      else if ((c == ']' || c == '}') && flow > 0) --flow;
      if (c != ' ' && c != '\t') last = k;
    }
    if (flow == 0 && last != std::string::npos) {
      std::size_t h = last;
      while (h > i && (std::isdigit(static_cast<unsigned char>(l[h])) || l[h] == '-' || l[h] == '+')) --h;
      if ((l[h] == '|' || l[h] == '>') && (h == i || l[h - 1] == ' ' || l[h - 1] == '\t'))
        blockParent = static_cast<int>(i);
    }
  }
}

}  // namespace

Teuchos::RCP<Teuchos::ParameterList> parseYaml(const std::string& text, const std::string& path) {
  refuseLeadingComma(text, path);
  YAML::Node root;
  try {
    // Every document: YAML::Load reads the first and ignored the rest, so a
    // scene pasted twice after "---" ran the first silently (found by a
    // review). A scene file holds one.
    const std::vector<YAML::Node> documents = YAML::LoadAll(text);
    if (!documents.empty()) root = documents.front();
    for (std::size_t d = 1; d < documents.size(); ++d)
      CMS_INPUT_CHECK(!documents[d].IsNull(),
                      where(path, documents[d]) << ": a second YAML document (after \"---\"): a scene file holds "
                                                   "one scene");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": not a valid scene file (" + e.msg + ")");
  }
  CMS_INPUT_CHECK(!root.IsMap() || root.size() != 1,
                  path << ": not a valid scene file (one top-level key, \"Scene\", holding the scene)");
  const auto top = root.begin();
  CMS_INPUT_CHECK(!top->first.IsScalar(), path << ": not a valid scene file (the top-level key must be a name)");
  auto p = Teuchos::rcp(new Teuchos::ParameterList(top->first.Scalar()));
  CMS_INPUT_CHECK(!top->second.IsMap(), where(path, top->second)
                                            << ": not a valid scene file (\"" << top->first.Scalar()
                                            << "\" must hold a mapping of keys)");
  fill(*p, top->second, path);
  return p;
}

}  // namespace cms::scene::detail
