// The input fuzz driver (issue 14 item 10): mutated scenes (YAML), Gmsh
// meshes (.msh ASCII and binary, .geo scripts), Matrix Market sidecars and
// their matrices, read in-process by the scene checker and the readers.
//
//   cms_fuzz_driver --count=3000 --seed=1     # the `unit` run (ctest fuzz_driver_short)
//   cms_fuzz_driver --count=100000 --seed=2   # the `slow` run (ctest fuzz_driver_long)
//   cms_fuzz_driver --count=0                 # only the regression inputs
//
// Every case is reproducible from (seed, case number): its kind, its seed
// file and its mutations are drawn from std::mt19937(seed * 1000003 + case).
// The outcomes:
//   accepted       the reader returned a consistent result;
//   input error    cms::InputError whose message names the file and a key,
//                  line, section or entry (file:line, Scene/..., "Key",
//                  $Section, line N, row/column/entry N): exit code 2 of cms;
//   bad message    an InputError that does not say where: a failure;
//   other error    any other exception (a NumericalError, a Teuchos or std
//                  exception): a failure;
//   crash / hang   the worker died of a signal, or one read took longer than
//                  --case-seconds (SIGALRM): a failure.
// Reads run in a forked worker (under a 4 GB address-space limit), restarted
// after the case that killed it. Failing inputs are written to --keep (kept
// as regressions under tests/data/fuzz/<kind>/regressions once fixed); the
// files in those folders are read first, as they are, on every run.
// Exit 0 when there is no failure, 1 otherwise.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include <Teuchos_DefaultComm.hpp>

#include "LimitedChild.hpp"
#include "TempFiles.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/MatrixSubstructureFile.hpp"
#include "cms/mesh/Mesh.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/substructure/Substructure.hpp"

namespace fs = std::filesystem;

namespace {

constexpr rlim_t kAddressSpace = 4000000000ull;
constexpr long kBatch = 2000;  // cases a worker reads before a fresh one takes over

using cms::fixtures::slurp;

void spit(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::vector<fs::path> filesIn(const fs::path& dir, const std::vector<std::string>& extensions) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && std::find(extensions.begin(), extensions.end(), e.path().extension()) != extensions.end())
      out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

/// One to three corruptions: bytes, lines, numbers, tokens, and for text
/// formats the words of the format.
class Mutator {
public:
  Mutator(std::mt19937& rng, std::vector<std::string> words) : rng_(rng), words_(std::move(words)) {}

  std::string operator()(std::string s) {
    const int rounds = 1 + static_cast<int>(below(3));
    for (int r = 0; r < rounds; ++r) s = once(std::move(s));
    return s;
  }

private:
  std::size_t below(std::size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }
  struct Span {
    std::size_t begin, end;
  };
  static std::vector<Span> lines(const std::string& s) {
    std::vector<Span> out;
    for (std::size_t b = 0; b < s.size();) {
      std::size_t e = s.find('\n', b);
      e = e == std::string::npos ? s.size() : e + 1;
      out.push_back({b, e});
      b = e;
    }
    return out;
  }
  static bool numberChar(char c) { return std::isdigit(static_cast<unsigned char>(c)) || std::strchr(".-+eE", c); }
  static std::vector<Span> numbers(const std::string& s) {
    std::vector<Span> out;
    for (std::size_t i = 0; i < s.size();) {
      if (!std::isdigit(static_cast<unsigned char>(s[i])) || (i > 0 && std::isalpha(static_cast<unsigned char>(s[i - 1])))) {
        ++i;
        continue;
      }
      std::size_t b = i > 0 && (s[i - 1] == '-' || s[i - 1] == '.') ? i - 1 : i, j = i;
      while (j < s.size() && numberChar(s[j])) ++j;
      out.push_back({b, j});
      i = j;
    }
    return out;
  }

  std::string once(std::string s) {
    static const std::vector<std::string> hostile = {
        "1e308", "-1", "nan", "inf", "-inf", "99999999999", "0", "-0", "2147483648", "-2147483649", "4294967297",
        "18446744073709551615", "9223372036854775808", "1e-320", "0x10", "1.5", "", "1e", "3", "16", "2", "1e6",
        "1000000", "-1e309", "1e-300", "0.0"};
    const auto ls = lines(s);
    switch (below(12)) {
      case 0: s.resize(below(s.size() + 1)); break;  // truncate
      case 1:                                         // flip bytes
        for (std::size_t k = 0, n = 1 + below(6); k < n && !s.empty(); ++k) s[below(s.size())] ^= static_cast<char>(1 + below(255));
        break;
      case 2:
      case 3: {  // a number becomes hostile
        const auto ns = numbers(s);
        if (ns.empty()) break;
        const Span n = ns[below(ns.size())];
        s.replace(n.begin, n.end - n.begin, hostile[below(hostile.size())]);
        break;
      }
      case 4:  // delete a line
        if (!ls.empty()) {
          const Span l = ls[below(ls.size())];
          s.erase(l.begin, l.end - l.begin);
        }
        break;
      case 5:  // duplicate a line
        if (!ls.empty()) {
          const Span l = ls[below(ls.size())];
          s.insert(l.end, s.substr(l.begin, l.end - l.begin));
        }
        break;
      case 6: {  // swap two lines
        if (ls.size() < 2) break;
        std::size_t a = below(ls.size()), b = below(ls.size());
        if (a > b) std::swap(a, b);
        if (a == b) break;
        const std::string la = s.substr(ls[a].begin, ls[a].end - ls[a].begin), lb = s.substr(ls[b].begin, ls[b].end - ls[b].begin);
        s = s.substr(0, ls[a].begin) + lb + s.substr(ls[a].end, ls[b].begin - ls[a].end) + la + s.substr(ls[b].end);
        break;
      }
      case 7: {  // a binary count or tag becomes huge, zero or negative
        static const std::uint64_t values[] = {0xFFFFFFFFFFFFFFFFull, 0x7FFFFFFFull, 99999999999ull, 0x8000000000000000ull,
                                               0, 1, 0xFFFFFFFFull, 1ull << 40};
        const std::uint64_t v = values[below(std::size(values))];
        const std::size_t width = below(2) ? 8 : 4;
        if (s.size() < width) break;
        std::memcpy(&s[below(s.size() - width + 1)], &v, width);
        break;
      }
      case 8:
      case 9: {  // a word of the format where something else was
        if (s.empty() || words_.empty()) break;
        const std::size_t at = below(s.size());
        const std::size_t len = std::min(below(8), s.size() - at);
        s.replace(at, len, words_[below(words_.size())]);
        break;
      }
      case 10: {  // indentation changed (YAML) or a line moved into another block
        if (ls.empty()) break;
        const Span l = ls[below(ls.size())];
        if (below(2)) s.insert(l.begin, std::string(1 + below(4), ' '));
        else if (s.compare(l.begin, 2, "  ") == 0) s.erase(l.begin, 2);
        break;
      }
      default: {  // random bytes
        std::string junk(1 + below(12), '\0');
        for (char& c : junk) c = static_cast<char>(below(256));
        s.insert(below(s.size() + 1), junk);
        break;
      }
    }
    return s;
  }

  std::mt19937& rng_;
  std::vector<std::string> words_;
};

const std::vector<std::string> kYamlWords = {
    ":", "[", "]", "{", "}", "- ", "\t", "'", "\"", "&a ", "*a", "!!binary ", "? ", "|", ">", "#", "~", "null",
    "{a: b}", "[1, 2]", "Kind: C", "Kind: R", "Parent: bus", "Parent: hub", "Elements: 1000001", "Elements: 2",
    "Rate: -1", "Area: 0", "Basis: Full", "Basis: Modes", "Vectors: 0", "Vectors: 100000", "Clamp: ends",
    "Substructures:", "Beam:", "Rotor:", "Spin:", "Reduction:", "Finite Element Model:", "Mesh: no.msh",
    "Free Reference: start", "Number of Modes: 0", "Dense Limit: 1", "Speed Factor: 1e308", "Frequency Tolerance: -0", "Type: RigidFit",
    "Frame: Stationary", "Element Sets:", "Tip Mass: 1", "Free: true", "\n    x: 1\n"};
const std::vector<std::string> kGmshWords = {
    "$Nodes", "$EndNodes", "$Elements", "$EndElements", "$Entities", "$EndEntities", "$PhysicalNames",
    "$EndPhysicalNames", "$Periodic", "$NodeData", "$MeshFormat", "$EndMeshFormat", "2.2 0 8", "4.1 1 8", "\"",
    "\r", "\t", std::string(1, '\0')};
const std::vector<std::string> kGeoWords = {
    "Point(", "Line(", "Curve Loop(", "Plane Surface(", "Physical Surface(", "Physical Curve(", "Physical Point(",
    "Transfinite Curve{1} = ", "Extrude {0, 0, 1} { Surface{1}; }", "Mesh.ElementOrder = 2;",
    "Mesh.MeshSizeMax = 1e-9;", "SetFactory(\"OpenCASCADE\");", "Include \"x.geo\";", "For i In {1:1e9}",
    "EndFor", "Merge \"x.msh\";", "Exit;", "Abort;", "Error(\"x\");", "h = 1e-6;", "n = 1e7;", ";", "{", "}",
    "//", "/*", "Mesh 3;", "Save \"/tmp/x.msh\";", "Delete Model;", "Recombine Surface{1};"};
const std::vector<std::string> kSidecarWords = {
    "cms-substructure 1", "units SI", "matrix K", "matrix M", "matrix G1", "matrix KS1", "matrix KT1", "spin-axis",
    "spin-origin", "node", "set", "ux", "uy", "uz", "rx", "ry", "rz", "#", "\"", "\r", "\t", "/etc/passwd",
    "fuzz_K.mtx", "../x.mtx"};
const std::vector<std::string> kMtxWords = {
    "%%MatrixMarket matrix coordinate real general", "%%MatrixMarket matrix coordinate real symmetric",
    "%%MatrixMarket matrix array real general", "%%MatrixMarket matrix coordinate complex general",
    "%%MatrixMarket matrix coordinate pattern general", "%", " ", "\n", "18 18 252", "0 0 0", "19 1 1.0"};

/// A kind of input: its seed files, how a mutated copy is read, and the
/// words of its format.
struct Kind {
  std::string name;
  std::vector<fs::path> seeds;
  const std::vector<std::string>* words;
};

struct Config {
  long count = 3000;
  unsigned seed = 1;
  double caseSeconds = 20;
  fs::path data = CMS_TEST_DATA_DIR;
  fs::path scenes = CMS_SCENE_DIR;
  fs::path keep;
  fs::path work;
  long show = -1;  ///< print this case's kind, seed and bytes instead of running
};

/// A finished case as the worker reports it.
enum class Verdict { Accepted, InputError, BadMessage, OtherError, Crash, Hang };

/// An InputError must name the file and where in it: a line (file:line,
/// "line N"), a key path (Scene/...), a quoted key or value, a Gmsh
/// section ($Nodes), a matrix entry, row, column, node, set or entity; or
/// say what the whole file lacks ("empty", "no size line", "cannot open").
bool saysWhere(const std::string& what, const std::string& file) {
  if (what.find(file) == std::string::npos && what.find(fs::path(file).filename().string()) == std::string::npos)
    return false;
  static const std::regex where(
      R"((:\d+)|([Ll]ine \d+)|(Scene(/|:))|("[^"]*")|('[^']*')|(\$[A-Za-z]+)|(\b([Ee]ntry|[Rr]ow|[Cc]olumn|[Nn]odes?|[Ss]et|[Mm]atrix|[Hh]eader|size line|[Ee]lements?|[Ss]ection|[Gg]roup|[Tt]ag|[Vv]alue|[Cc]urve|[Ss]urface|[Vv]olume|[Pp]oint|[Ee]ntity)\b)|(empty|cannot open|cannot read|no [a-z' ]+|need a [a-z-]+ record|[Ee]nd of file))");
  std::string rest = what;
  const std::size_t at = rest.find(file);
  if (at != std::string::npos) rest.erase(at, file.size());
  return std::regex_search(rest, where);
}

class Worker {
public:
  explicit Worker(const Config& c) : c_(c) {}

  /// Reads one input; `file` is the path an InputError must name.
  Verdict read(const std::string& kind, const fs::path& input, const std::string& sceneText, const fs::path& scenePath,
               std::string& message) {
    try {
      if (kind == "scene") {
        if (sceneText.empty() && !scenePath.empty()) cms::scene::Scene::read(scenePath.string());
        else cms::scene::Scene::parse(sceneText, scenePath.string());
      } else if (kind == "msh" || kind == "geo") {
        const auto m = cms::mesh::readGmsh(input.string());
        if (m.coordinates.size() != 3 * m.nodeCount()) throw std::logic_error("coordinates do not match the nodes");
        for (const auto& g : m.groups)
          for (const auto& b : g.blocks)
            for (std::int64_t n : b.nodes)
              if (n < 0 || n >= static_cast<std::int64_t>(m.nodeCount())) throw std::logic_error("node index out of range");
      } else if (kind == "sidecar") {
        const auto f = cms::fem::readMatrixSubstructureFile(input.string());
        if (f.coordinates.size() != 3 * f.nodeIds.size()) throw std::logic_error("coordinates do not match the nodes");
      } else {  // a Matrix Market substructure: its sidecar and every matrix
        cms::substructure::Substructure::fromMatrixMarket(input.string(), comm());
      }
      return Verdict::Accepted;
    } catch (const cms::InputError& e) {
      message = e.what();
      const std::string file = kind == "scene" ? scenePath.string() : input.string();
      // A Matrix Market substructure's message may name its sidecar or the
      // matrix file at fault.
      const bool named = saysWhere(message, file) || (kind == "mtx" && saysWhere(message, (input.parent_path()).string()));
      return named ? Verdict::InputError : Verdict::BadMessage;
    } catch (const std::exception& e) {
      message = std::string(typeid(e).name()) + ": " + e.what();
      return Verdict::OtherError;
    } catch (...) {
      message = "a non-standard exception";
      return Verdict::OtherError;
    }
  }

private:
  Teuchos::RCP<const Teuchos::Comm<int>> comm() {
    if (comm_.is_null()) {
      int initialized = 0;
      MPI_Initialized(&initialized);
      if (!initialized) MPI_Init(nullptr, nullptr);
      comm_ = Teuchos::DefaultComm<int>::getComm();
    }
    return comm_;
  }
  const Config& c_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
};

/// Case k: a kind, a seed file and the mutated bytes.
struct Case {
  std::string kind, label;
  fs::path seed;
  std::string bytes;
};

class Driver {
public:
  explicit Driver(Config c) : c_(std::move(c)) {
    const fs::path fuzz = c_.data / "fuzz";
    auto add = [&](const std::string& name, std::vector<fs::path> seeds, const std::vector<std::string>* words) {
      if (!seeds.empty()) kinds_.push_back({name, std::move(seeds), words});
    };
    add("scene", filesIn(c_.scenes, {".yaml"}), &kYamlWords);
    add("msh", filesIn(fuzz / "gmsh", {".msh"}), &kGmshWords);
    add("geo", filesIn(fuzz / "geo", {".geo"}), &kGeoWords);
    add("sidecar", filesIn(fuzz / "sidecar", {".cms"}), &kSidecarWords);
    add("mtx", filesIn(fuzz / "matrix-market", {".cms", ".mtx"}), &kMtxWords);
    // Each seed as it is (it must be accepted), then the regressions.
    for (const auto& k : kinds_)
      for (const auto& s : k.seeds)
        if (k.name != "mtx" || s.extension() == ".cms") regressions_.push_back({k.name, s}), ++seedCount_;
    for (const auto& k : kinds_)
      for (const auto& r : filesIn(fuzz / (k.name == "msh" ? "gmsh" : k.name == "mtx" ? "matrix-market" : k.name) / "regressions",
                                   {".yaml", ".msh", ".geo", ".cms", ".mtx"}))
        regressions_.push_back({k.name, r});
  }

  Case make(long k) const {
    std::mt19937 rng(c_.seed * 1000003u + static_cast<std::uint32_t>(k));
    // Scenes and meshes are the most varied inputs: 3 in 10 cases each.
    static const char* draw[] = {"scene", "scene", "scene", "msh", "msh", "msh", "geo", "sidecar", "mtx", "mtx"};
    std::string want = draw[rng() % 10];
    const Kind* kind = &kinds_.front();
    for (const auto& kd : kinds_)
      if (kd.name == want) kind = &kd;
    Case out{kind->name, "", kind->seeds[rng() % kind->seeds.size()], ""};
    Mutator mutate(rng, *kind->words);
    out.bytes = mutate(slurp(out.seed));
    out.label = "case " + std::to_string(k) + " (" + out.kind + ", " + out.seed.filename().string() + ")";
    return out;
  }

  int run() {
    fs::create_directories(c_.work);
    const auto t0 = std::chrono::steady_clock::now();
    long next = -static_cast<long>(regressions_.size());  // regressions first, as negative case numbers
    while (next < c_.count) next = batch(next);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "cms_fuzz_driver: seed " << c_.seed << ", " << c_.count << " mutated inputs + "
              << regressions_.size() - seedCount_ << " regression inputs (and " << seedCount_ << " seeds) in " << seconds << " s\n";
    std::cout << "kind      accepted  input-error  bad-message  other-error  crash  hang\n";
    for (const auto& [kind, n] : tally_) {
      std::printf("%-9s %8ld %12ld %12ld %12ld %6ld %5ld\n", kind.c_str(), n[0], n[1], n[2], n[3], n[4], n[5]);
      for (int i = 0; i < 6; ++i) total_[i] += n[i];
    }
    std::printf("%-9s %8ld %12ld %12ld %12ld %6ld %5ld\n", "total", total_[0], total_[1], total_[2], total_[3], total_[4],
                total_[5]);
    for (const auto& f : failures_) std::cout << "FAILED " << f << '\n';
    std::cout << (failures_.empty() ? "PASSED" : "FAILED") << ": " << failures_.size() << " failures\n";
    return failures_.empty() ? 0 : 1;
  }

private:
  /// Runs cases [from, count) in a forked worker until it finishes or dies;
  /// returns the case to go on from.
  long batch(long from) {
    const auto child = cms::fixtures::forkLimited(kAddressSpace, [&](int fd) {
      Worker w(c_);
      auto say = [&](const std::string& s) {
        if (!cms::fixtures::writeAll(fd, s)) _exit(9);
      };
      // At most kBatch cases a worker: Gmsh 4.8 leaks a little per read.
      for (long k = from; k < std::min(c_.count, from + kBatch); ++k) {
        std::string kind, text;
        fs::path input, scenePath;
        if (k < 0) {
          const auto& [kd, file] = regressions_[static_cast<std::size_t>(k + static_cast<long>(regressions_.size()))];
          kind = kd;
          if (kind == "scene") scenePath = file;
          else input = copyRegression(kind, file);
        } else {
          const Case cs = make(k);
          kind = cs.kind;
          if (kind == "scene") text = cs.bytes, scenePath = cs.seed;
          else input = writeCase(cs);
        }
        say("S " + std::to_string(k) + "\n");
        std::string message;
        alarm(static_cast<unsigned>(c_.caseSeconds));  // readGmsh's .geo mesher times out first (main)
        const Verdict v = w.read(kind, input, text, scenePath, message);
        alarm(0);
        std::replace(message.begin(), message.end(), '\n', ' ');
        if (message.size() > 400) message = message.substr(0, 400) + "...";
        say("D " + std::to_string(k) + " " + std::to_string(static_cast<int>(v)) + " " + kind + " " + message + "\n");
      }
    });
    std::string buffer;
    long running = from - 1;  // last case started
    long done = from - 1;
    const int status = cms::fixtures::finish(child, [&](const char* chunk, std::size_t n) {
      buffer.append(chunk, n);
      for (std::size_t eol; (eol = buffer.find('\n')) != std::string::npos; buffer.erase(0, eol + 1)) {
        const std::string line = buffer.substr(0, eol);
        char tag = line[0];
        long k = std::strtol(line.c_str() + 2, nullptr, 10);
        if (tag == 'S') {
          running = k;
          continue;
        }
        std::istringstream fields(line.substr(2));
        long ignored = 0;
        int v = 0;
        std::string kind, message;
        fields >> ignored >> v >> kind;
        std::getline(fields, message);
        if (!message.empty() && message[0] == ' ') message.erase(0, 1);
        record(k, v, kind, message);
        done = k;
      }
    });
    if (WIFSIGNALED(status) || (WIFEXITED(status) && WEXITSTATUS(status) != 0)) {
      if (running > done) {
        const int sig = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
        record(running, sig == SIGALRM ? 5 : 4, kindOf(running),
               sig == SIGALRM ? "hung (over " + std::to_string(static_cast<int>(c_.caseSeconds)) + " s)"
                              : sig ? "crashed (signal " + std::to_string(sig) + ")"
                                    : "the worker exited with " + std::to_string(WEXITSTATUS(status)));
        return running + 1;
      }
      failures_.push_back("the worker ended without a case running (status " + std::to_string(status) + ")");
    }
    return std::max(std::min(c_.count, from + kBatch), done + 1);
  }

  fs::path writeCase(const Case& cs) const {
    if (cs.kind == "mtx") {  // the whole substructure, one of its files mutated
      const fs::path dir = c_.work / "mm";
      fs::create_directories(dir);
      for (const auto& f : filesIn(cs.seed.parent_path(), {".cms", ".mtx"}))
        spit(dir / f.filename(), f == cs.seed ? cs.bytes : slurp(f));
      return dir / "fuzz.cms";
    }
    const fs::path file = c_.work / ("input" + cs.seed.extension().string());
    spit(file, cs.bytes);
    return file;
  }

  fs::path copyRegression(const std::string& kind, const fs::path& file) const {
    if (kind == "mtx") {  // regressions/<name>.<cms|mtx> replaces that file of the seed substructure
      const fs::path dir = c_.work / "mm";
      fs::create_directories(dir);
      for (const auto& f : filesIn(c_.data / "fuzz" / "matrix-market", {".cms", ".mtx"})) spit(dir / f.filename(), slurp(f));
      const std::string name = file.stem().string();
      const std::string target = name.substr(name.rfind('.') == std::string::npos ? 0 : name.rfind('.') + 1);
      spit(dir / (target + file.extension().string()), slurp(file));
      return dir / "fuzz.cms";
    }
    const fs::path input = c_.work / ("input" + file.extension().string());
    spit(input, slurp(file));
    return input;
  }

  std::string describe(long k) const {
    if (k < 0) {
      const auto& [kind, file] = regressions_[static_cast<std::size_t>(k + static_cast<long>(regressions_.size()))];
      return "regression " + file.string() + " (" + kind + ")";
    }
    return make(k).label;
  }

  std::string kindOf(long k) const {
    return k < 0 ? regressions_[static_cast<std::size_t>(k + static_cast<long>(regressions_.size()))].first : make(k).kind;
  }

  void record(long k, int verdict, const std::string& kind, const std::string& message) {
    if (k < 0 && k + static_cast<long>(regressions_.size()) < seedCount_) {  // an unmodified seed
      if (verdict != 0) failures_.push_back(describe(k) + ": the seed itself is refused: " + message);
      return;
    }
    ++tally_[kind][verdict];
    if (verdict == 1 && std::getenv("CMS_FUZZ_MESSAGES")) std::cout << "message " << describe(k) << ": " << message << '\n';
    if (verdict == 0 || verdict == 1) return;
    static const char* what[] = {"", "", "an input error that does not say where", "not an input error", "", ""};
    std::string entry = describe(k) + ": " + what[verdict] + (what[verdict][0] ? ": " : "") + message;
    if (k >= 0 && !c_.keep.empty()) {
      const Case cs = make(k);
      fs::create_directories(c_.keep);
      const fs::path kept = c_.keep / (cs.kind + "-seed" + std::to_string(c_.seed) + "-case" + std::to_string(k) + "." +
                                       cs.seed.filename().string());
      spit(kept, cs.bytes);
      entry += " (input kept as " + kept.string() + ")";
    }
    failures_.push_back(entry);
  }

  Config c_;
  std::vector<Kind> kinds_;
  std::vector<std::pair<std::string, fs::path>> regressions_;  ///< the seeds, then the regression inputs
  long seedCount_ = 0;
  std::map<std::string, std::array<long, 6>> tally_;
  long total_[6] = {0, 0, 0, 0, 0, 0};
  std::vector<std::string> failures_;
};

}  // namespace

int main(int argc, char** argv) {
  Config c;
  c.work = (fs::is_directory("/dev/shm") && access("/dev/shm", W_OK) == 0 ? fs::path("/dev/shm") : fs::temp_directory_path()) /
           ("cms_fuzz_driver_" + std::to_string(getpid()));
  c.keep = fs::temp_directory_path() / "cms_fuzz_failures";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* key) -> const char* {
      const std::size_t n = std::strlen(key);
      return a.compare(0, n, key) == 0 ? a.c_str() + n : nullptr;
    };
    if (const char* v = value("--count=")) c.count = std::atol(v);
    else if (const char* v = value("--seed=")) c.seed = static_cast<unsigned>(std::strtoul(v, nullptr, 10));
    else if (const char* v = value("--case-seconds=")) c.caseSeconds = std::atof(v);
    else if (const char* v = value("--data=")) c.data = v;
    else if (const char* v = value("--scenes=")) c.scenes = v;
    else if (const char* v = value("--keep=")) c.keep = v;
    else if (const char* v = value("--show=")) c.show = std::atol(v);
    else {
      std::cerr << "usage: cms_fuzz_driver [--count=N] [--seed=S] [--case-seconds=T] [--data=DIR] [--scenes=DIR] "
                   "[--keep=DIR] [--show=CASE]\n";
      return 2;
    }
  }
  if (c.count < 0 || c.caseSeconds < 1) {
    std::cerr << "cms_fuzz_driver: --count must be >= 0 and --case-seconds >= 1\n";
    return 2;
  }
  // readGmsh meshes a .geo in a child process it kills after
  // $CMS_GEO_TIME_LIMIT seconds (default 600): here 1 s (the seeds mesh in
  // ~0.02 s; each of the ~30 replayed regressions that hang Gmsh costs the
  // limit), so that a hanging mesher is the input error readGmsh reports,
  // not a hung case.
  if (!std::getenv("CMS_GEO_TIME_LIMIT")) setenv("CMS_GEO_TIME_LIMIT", "1", 1);
  int rc = 1;
  try {
    if (c.show >= 0) {
      const auto cs = Driver(c).make(c.show);
      std::cerr << cs.label << '\n';
      std::cout << cs.bytes;
      return 0;
    }
    rc = Driver(c).run();
  } catch (const std::exception& e) {
    std::cerr << "cms_fuzz_driver: " << e.what() << '\n';
  }
  std::error_code ec;
  fs::remove_all(c.work, ec);
  return rc;
}
