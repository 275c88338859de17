// Randomised corruption of valid Gmsh meshes, Abaqus/CalculiX decks and
// sidecars: the readers must
// either succeed or throw cms::InputError. Any other exception, a crash, a
// hang, a leaked file descriptor or an allocation past a 4 GB address-space
// limit fails the test.
//
// Seeds are the files in tests/data/fuzz/gmsh/, inp/ and sidecar/;
// each gets CMS_FUZZ_ITERATIONS mutated copies (default below: the whole test
// in a few seconds). A case is reproducible from its seed file and number
// alone. Files in the regressions/ folders are inputs that once broke a
// reader; they are read as they are.
//
// Each seed runs in a child process: a crash or hang there is reported with
// the case that caused it (its input is copied next to the work folder), the
// memory limit applies without the caller's `ulimit -v`, and the memory Gmsh
// 4.8 leaks per initialize/finalize pair (see Mesh.cpp) is returned with the
// child instead of adding up over a long run.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#include "LimitedChild.hpp"
#include "TempFiles.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/MatrixSubstructureFile.hpp"
#include "cms/mesh/Mesh.hpp"

#ifndef CMS_TEST_DATA_DIR
#define CMS_TEST_DATA_DIR "tests/data"
#endif

namespace fs = std::filesystem;

namespace {

const fs::path kFuzz = fs::path(CMS_TEST_DATA_DIR) / "fuzz";
constexpr int kDefaultIterations = 3000;
constexpr rlim_t kAddressSpace = 4000000000ull;  // bytes, as `ulimit -v 4000000`
constexpr unsigned kCaseSeconds = 20;            // one read taking longer is a hang

int iterations() {
  const char* env = std::getenv("CMS_FUZZ_ITERATIONS");
  if (!env || !*env) return kDefaultIterations;
  char* end = nullptr;
  const long n = std::strtol(env, &end, 10);
  if (*end != '\0' || n < 0 || n > 100000000) {
    ADD_FAILURE() << "CMS_FUZZ_ITERATIONS=\"" << env << "\" is not a count";
    return kDefaultIterations;
  }
  return static_cast<int>(n);
}

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename().string().front() != '.' && e.path().extension() != ".md")
      out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

using cms::fixtures::slurp;

void spit(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::uint32_t nameHash(const std::string& s) {  // FNV-1a: stable across runs and platforms
  std::uint32_t h = 2166136261u;
  for (unsigned char c : s) h = (h ^ c) * 16777619u;
  return h;
}

std::size_t openDescriptors() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

/// The words of the Gmsh and sidecar formats that a mutation may insert.
const std::vector<std::string>& gmshWords() {
  static const std::vector<std::string> words = {
      "$Nodes", "$EndNodes", "$Elements", "$EndElements", "$Entities", "$PhysicalNames", "$Periodic",
      "$NodeData", "$MeshFormat", "node", "set", "matrix", "units", "spin-axis", "cms-substructure", "K",
      "M", "G1", "ux", "rz", "#", "\"", "SI", "\r", "\t", std::string(1, '\0')};
  return words;
}

/// The same for Abaqus/CalculiX decks: keywords, parameters, separators.
const std::vector<std::string>& inpWords() {
  static const std::vector<std::string> words = {
      "*NODE", "*ELEMENT, TYPE=C3D20", "*ELEMENT, TYPE=C3D8R", "*NSET, NSET=", "*ELSET, ELSET=", "GENERATE",
      "*INCLUDE, INPUT=", "*INCLUDE, INPUT=input.inp", "*INCLUDE, INPUT=part.inp", "**", "*", ",", ",\n", "=",
      "\n", "ELSET=", "NSET=", "C3D15", "B31", "S4R", "*STEP", "*NGEN", "\"", "\r", "\t", std::string(1, '\0')};
  return words;
}

/// One to three random corruptions of a text or binary file; `words` are
/// the format's own tokens, inserted in place of a few bytes.
class Mutator {
public:
  explicit Mutator(std::uint32_t seed, const std::vector<std::string>& words = gmshWords())
      : rng_(seed), words_(words) {}

  std::string operator()(std::string s) {
    const int rounds = 1 + static_cast<int>(below(3));
    for (int r = 0; r < rounds; ++r) s = once(std::move(s));
    return s;
  }

private:
  std::size_t below(std::size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
  }
  template <class T>
  const T& pick(const std::vector<T>& v) {
    return v[below(v.size())];
  }

  struct Span {
    std::size_t begin, end;
  };
  static std::vector<Span> lines(const std::string& s) {
    std::vector<Span> out;
    std::size_t b = 0;
    while (b < s.size()) {
      std::size_t e = s.find('\n', b);
      e = e == std::string::npos ? s.size() : e + 1;
      out.push_back({b, e});
      b = e;
    }
    return out;
  }
  static bool numberChar(char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
  }
  static std::vector<Span> numbers(const std::string& s) {
    std::vector<Span> out;
    for (std::size_t i = 0; i < s.size();) {
      if (!numberChar(s[i]) || (i > 0 && std::isalpha(static_cast<unsigned char>(s[i - 1])))) {
        ++i;
        continue;
      }
      std::size_t j = i;
      bool digit = false;
      while (j < s.size() && numberChar(s[j])) digit |= std::isdigit(static_cast<unsigned char>(s[j++])) != 0;
      if (digit) out.push_back({i, j});
      i = j;
    }
    return out;
  }
  // "$Name ... $EndName" blocks, binary data included.
  static std::vector<Span> sections(const std::string& s) {
    std::vector<Span> out;
    for (std::size_t b = 0; (b = s.find('$', b)) != std::string::npos; ++b) {
      if ((b > 0 && s[b - 1] != '\n') || s.compare(b, 4, "$End") == 0) continue;
      const std::size_t eol = s.find('\n', b);
      if (eol == std::string::npos) break;
      const std::string end = "\n$End" + s.substr(b + 1, eol - b);
      const std::size_t e = s.find(end, eol);
      if (e != std::string::npos) out.push_back({b, e + end.size()});
    }
    return out;
  }
  static std::string swapped(const std::string& s, Span x, Span y) {
    return s.substr(0, x.begin) + s.substr(y.begin, y.end - y.begin) + s.substr(x.end, y.begin - x.end) +
           s.substr(x.begin, x.end - x.begin) + s.substr(y.end);
  }

  std::string once(std::string s) {
    static const std::vector<std::string> hostile = {
        "1e308", "-1", "nan", "inf", "-inf", "99999999999", "0", "-0", "2147483648", "-2147483649",
        "4294967297", "18446744073709551615", "9223372036854775808", "1e-320", "0x10", "1.5", "", "1e",
        "00000000000000000000000000000000001", "3", "16", "2"};
    const std::vector<Span> ls = lines(s);
    switch (below(11)) {
      case 0:  // truncate
        s.resize(below(s.size() + 1));
        break;
      case 1: {  // flip a few bytes
        const std::size_t n = 1 + below(8);
        for (std::size_t k = 0; k < n && !s.empty(); ++k) {
          const std::size_t at = below(s.size());
          s[at] ^= static_cast<char>(1 + below(255));
        }
        break;
      }
      case 2:
      case 3: {  // a number becomes something hostile
        const auto ns = numbers(s);
        if (ns.empty()) break;
        const Span n = pick(ns);
        s.replace(n.begin, n.end - n.begin, pick(hostile));
        break;
      }
      case 4:  // delete a line
        if (!ls.empty()) {
          const Span l = pick(ls);
          s.erase(l.begin, l.end - l.begin);
        }
        break;
      case 5:  // duplicate a line
        if (!ls.empty()) {
          const Span l = pick(ls);
          s.insert(l.end, s.substr(l.begin, l.end - l.begin));
        }
        break;
      case 6: {  // swap two sections
        const auto ss = sections(s);
        if (ss.size() < 2) break;
        std::size_t a = below(ss.size()), b = below(ss.size() - 1);
        if (b >= a) ++b;
        if (a > b) std::swap(a, b);
        if (ss[a].end <= ss[b].begin) s = swapped(s, ss[a], ss[b]);
        break;
      }
      case 7: {  // a binary count or tag becomes huge, zero or negative
        static const std::uint64_t values[] = {0xFFFFFFFFFFFFFFFFull, 0x7FFFFFFFull, 99999999999ull,
                                               0x8000000000000000ull, 0, 1, 0xFFFFFFFFull, 1ull << 40};
        const std::uint64_t v = values[below(std::size(values))];
        const std::size_t width = below(2) ? 8 : 4;
        if (s.size() < width) break;
        std::memcpy(&s[below(s.size() - width + 1)], &v, width);
        break;
      }
      case 8: {  // swap two lines
        if (ls.size() < 2) break;
        std::size_t a = below(ls.size()), b = below(ls.size());
        if (a > b) std::swap(a, b);
        if (a != b) s = swapped(s, ls[a], ls[b]);
        break;
      }
      case 9: {  // a keyword where something else was
        if (s.empty()) break;
        // One draw per statement: argument evaluation order is unspecified.
        const std::size_t at = below(s.size());
        const std::size_t len = std::min(below(8), s.size() - at);
        s.replace(at, len, pick(words_));
        break;
      }
      default: {  // insert random bytes
        std::string junk(1 + below(16), '\0');
        for (char& c : junk) c = static_cast<char>(below(256));
        s.insert(below(s.size() + 1), junk);
        break;
      }
    }
    return s;
  }

  std::mt19937 rng_;
  const std::vector<std::string>& words_;
};

/// Memory-backed when possible: rewriting a file on a disk mounted with
/// `discard` costs a trim per case, ten times the read itself.
fs::path scratchRoot() {
  std::error_code ec;
  if (fs::is_directory("/dev/shm", ec) && access("/dev/shm", W_OK) == 0) return "/dev/shm";
  return fs::temp_directory_path();
}

/// A fresh folder for the input being read.
class WorkDir {
public:
  WorkDir() : path_(scratchRoot() / ("cms_fuzz_" + std::to_string(getpid()))) { fs::create_directories(path_); }
  ~WorkDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

private:
  fs::path path_;
};

/// An accepted input the caller cannot use: not an input error, a bug.
struct Broken : std::logic_error {
  using std::logic_error::logic_error;
};

void readMesh(const std::string& path) {
  const cms::mesh::Mesh m = cms::mesh::readMesh(path);  // by extension: Gmsh or .inp
  auto check = [](bool ok, const char* what) {
    if (!ok) throw Broken(what);
  };
  check(m.coordinates.size() == 3 * m.nodeCount(), "coordinates do not match the nodes");
  check(!m.groups.empty(), "no groups");
  for (double x : m.coordinates) check(std::isfinite(x), "a non-finite coordinate");
  for (const auto& g : m.groups) {
    check(!g.blocks.empty(), "a group without cells");
    for (const auto& b : g.blocks) {
      check(b.nodes.size() == b.size() * static_cast<std::size_t>(b.nodesPerCell), "block sizes disagree");
      for (std::int64_t n : b.nodes) check(n >= 0 && n < static_cast<std::int64_t>(m.nodeCount()), "node index out of range");
    }
  }
}

void readSidecar(const std::string& path) {
  const auto f = cms::fem::readMatrixSubstructureFile(path);
  auto check = [](bool ok, const char* what) {
    if (!ok) throw Broken(what);
  };
  check(!f.nodeIds.empty(), "no nodes");
  check(f.coordinates.size() == 3 * f.nodeIds.size(), "coordinates do not match the nodes");
  check(f.components.size() == f.nodeIds.size(), "components do not match the nodes");
  check(f.rowOffsets().back() == f.dofCount(), "row offsets disagree with the DOF count");
  check(f.matrices.count("K") && f.matrices.count("M"), "K or M missing");
}

using Reader = std::function<void(const std::string&)>;

/// What a child reports: counts, then one line per failure.
struct Outcome {
  long accepted = 0, rejected = 0;
  std::vector<std::string> failures;
};

fs::path keptCopy(const fs::path& file, const std::string& label) {
  const fs::path kept =
      scratchRoot() / ("cms_fuzz_failure_" + std::to_string(nameHash(label)) + file.extension().string());
  std::error_code ec;
  fs::copy_file(file, kept, fs::copy_options::overwrite_existing, ec);
  return kept;
}

/// Read one input in this (child) process; anything but success or
/// cms::InputError naming the file is a failure. `progress` names the case
/// and its file first, for the parent should the read never return.
void readOne(const Reader& read, const fs::path& file, const std::string& label, const fs::path& progress,
             Outcome& out) {
  spit(progress, label + "\n" + file.string());
  const std::size_t descriptors = openDescriptors();
  std::string failure;
  alarm(kCaseSeconds);
  try {
    read(file.string());
    ++out.accepted;
  } catch (const cms::InputError& e) {
    ++out.rejected;
    if (std::string(e.what()).find(file.string()) == std::string::npos)
      failure = "the message does not name the file: " + std::string(e.what());
  } catch (const std::exception& e) {
    failure = std::string(typeid(e).name()) + ": " + e.what();
  } catch (...) {
    failure = "a non-standard exception";
  }
  alarm(0);
  // Gmsh leaves its FILE open when it fails part-way through a read; the
  // scan before it must keep that from happening.
  if (failure.empty() && openDescriptors() != descriptors) failure = "the read leaked a file descriptor";
  if (!failure.empty())
    out.failures.push_back(label + ": " + failure + " (input kept as " + keptCopy(file, label).string() + ")");
}

/// Runs job(outcome) in a child process under the memory limit; a crash or
/// hang is pinned on the case named in `progress` (see readOne).
Outcome inChild(const std::function<void(Outcome&)>& job, const fs::path& progress) {
  const auto child = cms::fixtures::forkLimited(kAddressSpace, [&](int fd) {
    Outcome out;
    try {
      job(out);
    } catch (const std::exception& e) {
      out.failures.push_back(std::string("the harness itself failed: ") + e.what());
    }
    std::string report = std::to_string(out.accepted) + " " + std::to_string(out.rejected) + "\n";
    for (const std::string& f : out.failures) report += f + "\n";
    cms::fixtures::writeAll(fd, report);
  });
  std::string report;
  const int status = cms::fixtures::finish(child, [&](const char* data, std::size_t n) { report.append(data, n); });
  Outcome out;
  const std::string where = slurp(progress);
  const std::string label = where.substr(0, where.find('\n'));
  const fs::path input = where.find('\n') == std::string::npos ? fs::path() : fs::path(where.substr(where.find('\n') + 1));
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    out.failures.push_back(label + ": the reader " +
                           (sig == SIGALRM ? "hung (over " + std::to_string(kCaseSeconds) + " s)"
                                           : "crashed (signal " + std::to_string(sig) + ")") +
                           " (input kept as " + keptCopy(input, label).string() + ")");
    return out;
  }
  std::size_t eol = report.find('\n');
  if (eol == std::string::npos || std::sscanf(report.c_str(), "%ld %ld", &out.accepted, &out.rejected) != 2) {
    out.failures.push_back(label + ": the child ended without a report");
    return out;
  }
  for (std::size_t b = eol + 1; b < report.size(); b = eol + 1) {
    eol = report.find('\n', b);
    if (eol == std::string::npos) eol = report.size();
    out.failures.push_back(report.substr(b, eol - b));
  }
  return out;
}

void fuzzFolder(const fs::path& dir, const Reader& read, const std::vector<std::string>& words = gmshWords()) {
  const std::vector<fs::path> seeds = filesIn(dir);
  ASSERT_FALSE(seeds.empty()) << "no seed files in " << dir;
  const int n = iterations();
  WorkDir work;
  const fs::path progress = work.path() / "progress";
  long accepted = 0, rejected = 0;
  auto collect = [&](const Outcome& o) {
    accepted += o.accepted;
    rejected += o.rejected;
    for (const std::string& f : o.failures) ADD_FAILURE() << f;
  };
  for (const fs::path& seed : seeds) {
    const std::string name = seed.filename().string();
    const std::string original = slurp(seed);
    const fs::path file = work.path() / ("input" + seed.extension().string());
    const Outcome o = inChild(
        [&](Outcome& out) {
          spit(file, original);
          readOne(read, file, name + " (unmodified)", progress, out);
          if (out.rejected > 0) out.failures.push_back("seed " + name + " itself is rejected");
          for (int i = 0; i < n; ++i) {
            const std::string label = name + " case " + std::to_string(i);
            Mutator mutate(nameHash(name) * 1000003u + static_cast<std::uint32_t>(i), words);
            spit(file, mutate(original));
            readOne(read, file, label, progress, out);
          }
        },
        progress);
    collect(o);
  }
  const Outcome o = inChild(
      [&](Outcome& out) {
        for (const fs::path& regression : filesIn(dir / "regressions")) {
          const std::string label = "regression " + regression.filename().string();
          const fs::path file = work.path() / ("input" + regression.extension().string());
          spit(file, slurp(regression));
          readOne(read, file, label, progress, out);
        }
      },
      progress);
  collect(o);
  std::cout << "[ fuzz     ] " << dir.filename().string() << ": " << seeds.size() << " seeds x " << n
            << " cases + regressions: " << accepted << " accepted, " << rejected << " rejected\n";
}

TEST(MeshReaderFuzz, GmshFiles) { fuzzFolder(kFuzz / "gmsh", readMesh); }

// Decks may include "part.inp" (tests/data/fuzz/inp/include/part.inp, written
// beside each input, not mutated): includes are fuzzed by the names and
// keywords the mutations make, cycles among them.
void readDeck(const std::string& path) {
  const fs::path part = fs::path(path).parent_path() / "part.inp";
  if (!fs::exists(part)) spit(part, slurp(kFuzz / "inp" / "include" / "part.inp"));
  readMesh(path);
}

TEST(MeshReaderFuzz, InpDecks) { fuzzFolder(kFuzz / "inp", readDeck, inpWords()); }

TEST(MeshReaderFuzz, Sidecars) { fuzzFolder(kFuzz / "sidecar", readSidecar); }

}  // namespace
