// Randomised corruption of a Matrix Market substructure (sidecar and matrix
// files): reading it must either succeed or throw cms::InputError, the same
// on every rank; anything else (another exception, a crash, a rank left
// waiting: a hang caught by CTest's timeout) fails. Seeds are written by the
// framework itself from a small spinning beam; mutations are deterministic
// (std::mt19937 seeded by the iteration), count from CMS_FUZZ_ITERATIONS.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>

#include "BeamModels.hpp"
#include "cms/core/Error.hpp"
#include "cms/substructure/Substructure.hpp"

using namespace cms;
using substructure::Substructure;

namespace {

auto world() { return Teuchos::DefaultComm<int>::getComm(); }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A small clamped beam (`name`, spinning about z or not) written as a
/// Matrix Market substructure to a temporary directory, returned. From a
/// one-rank assembly, so every rank count reads the same bytes. Collective.
std::string writtenBeam(const std::string& name, bool spinning) {
  auto sec = fixtures::beamSection(1e-3, 1e-7, 2e-7, 2e-7, {0, 1, 0});
  auto model = fixtures::frameModel(fixtures::lineMesh(1.0, 3), {7e10, 0.33, 2700.0}, sec);
  model.name = name;
  model.fixed.push_back({"root", "root", {}, true});
  if (spinning) {
    fem::SpinDefinition spin;
    spin.spin.axis = {0.0, 0.0, 1.0};
    model.spin = spin;
  }
  const auto comm = world();
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("cms_mm_" + name + "_np" + std::to_string(comm->getSize()))).string();
  const auto self = comm->split(comm->getRank(), 0);
  if (comm->getRank() == 0) Substructure::fromFiniteElementModel(model, self).writeMatrixMarket(dir);
  comm->barrier();
  return dir;
}

std::string mutate(std::string s, std::mt19937& rng) {
  auto pick = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  static const char* tokens[] = {"0", "-1", "1e308", "nan", "inf", "99999999999", "2147483648", " ", "\n", "%",
                                 "#", "x", "1.5", "-0", "18446744073709551616", "\t", "\r\n"};
  switch (pick(6)) {
    case 0:  // truncate
      s.resize(pick(s.size() + 1));
      break;
    case 1:  // flip bytes
      for (std::size_t k = 0, n = 1 + pick(4); k < n && !s.empty(); ++k) s[pick(s.size())] = static_cast<char>(pick(256));
      break;
    case 2: {  // replace a number-like token by a nasty one
      const std::size_t at = pick(s.size() + 1);
      std::size_t end = at;
      while (end < s.size() && s[end] != ' ' && s[end] != '\n') ++end;
      s.replace(at, end - at, tokens[pick(sizeof tokens / sizeof *tokens)]);
      break;
    }
    case 3: {  // delete a line
      const std::size_t at = s.rfind('\n', pick(s.size() + 1));
      const std::size_t b = at == std::string::npos ? 0 : at + 1, e = s.find('\n', b);
      s.erase(b, e == std::string::npos ? std::string::npos : e - b + 1);
      break;
    }
    case 4: {  // duplicate a line
      const std::size_t b = s.rfind('\n', pick(s.size() + 1));
      const std::size_t from = b == std::string::npos ? 0 : b + 1, e = s.find('\n', from);
      const std::string line = s.substr(from, e == std::string::npos ? std::string::npos : e - from + 1);
      s.insert(from, line);
      break;
    }
    default:  // insert a token
      s.insert(pick(s.size() + 1), tokens[pick(sizeof tokens / sizeof *tokens)]);
  }
  return s;
}

}  // namespace

TEST(MatrixMarketFuzz, CorruptedFilesGiveInputErrorOrSucceedOnEveryRank) {
  const auto comm = world();
  const std::string dir = writtenBeam("fuzz", true);
  const std::vector<std::string> targets = {dir + "/fuzz.cms", dir + "/fuzz_K.mtx", dir + "/fuzz_G1.mtx"};
  std::vector<std::string> seeds;
  for (const auto& t : targets) seeds.push_back(slurp(t));

  const char* env = std::getenv("CMS_FUZZ_ITERATIONS");
  const int iterations = env ? std::atoi(env) : 300;
  int accepted = 0, refused = 0;
  for (int i = 0; i < iterations; ++i) {
    std::mt19937 rng(static_cast<unsigned>(i));
    const std::size_t which = static_cast<std::size_t>(i) % targets.size();
    comm->barrier();
    if (comm->getRank() == 0) {
      for (std::size_t t = 0; t < targets.size(); ++t)
        std::ofstream(targets[t], std::ios::binary | std::ios::trunc)
            << (t == which ? mutate(seeds[t], rng) : seeds[t]);
    }
    comm->barrier();
    int outcome = 0;  // 0 read, 1 InputError, 2 anything else
    std::string what;
    try {
      Substructure::fromMatrixMarket(targets[0], comm);
    } catch (const InputError& e) {
      outcome = 1;
    } catch (const std::exception& e) {
      outcome = 2;
      what = e.what();
    }
    int lo = 0, hi = 0;
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MIN, outcome, Teuchos::outArg(lo));
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, outcome, Teuchos::outArg(hi));
    ASSERT_EQ(lo, hi) << "ranks disagree on iteration " << i << " (" << targets[which] << ")";
    ASSERT_NE(outcome, 2) << "iteration " << i << ", " << targets[which] << ": not an InputError: " << what;
    (outcome == 0 ? accepted : refused)++;
    if (std::getenv("CMS_FUZZ_VERBOSE") && comm->getRank() == 0) std::printf("iteration %d: %d\n", i, outcome);
  }
  if (comm->getRank() == 0) std::printf("%d corrupted inputs: %d read, %d refused\n", iterations, accepted, refused);
  EXPECT_GT(refused, iterations / 2);  // the mutations do break most files
}

// Two readings of one file (found by a review): the check before Tpetra's
// reader took a repeated entry as one more entry, and Tpetra sums repeats
// (K(1,1) doubled, and mirrored in a symmetric file, where no later
// symmetry check can see it); and strtod read a hexadecimal value
// (0x1908B100 = 4.2e8) that Tpetra's stream reads as 0. Both are refused
// with the file and line, on every rank.
TEST(MatrixMarketFile, RepeatedEntriesAndNonDecimalValuesAreRefused) {
  const auto comm = world();
  const std::string dir = writtenBeam("twice", false);
  const std::string K = dir + "/twice_K.mtx", seed = slurp(K);
  // The first entry line (after the banner, the comments and the size line).
  std::size_t sizeLine = 0;
  while (seed[sizeLine] == '%') sizeLine = seed.find('\n', sizeLine) + 1;
  const std::size_t first = seed.find('\n', sizeLine) + 1, firstEnd = seed.find('\n', first) + 1;
  const std::string entry = seed.substr(first, firstEnd - first);
  std::istringstream header(seed.substr(sizeLine, first - sizeLine));
  long long m = 0, n = 0, nnz = 0;
  header >> m >> n >> nnz;
  const std::string sizeText = std::to_string(m) + " " + std::to_string(n) + " ";
  const std::string repeated = seed.substr(0, sizeLine) + sizeText + std::to_string(nnz + 1) + "\n" + entry +
                               seed.substr(first);
  std::istringstream e(entry);
  long long i = 0, j = 0;
  e >> i >> j;
  const std::string hex = seed.substr(0, first) + std::to_string(i) + " " + std::to_string(j) + " 0x1908B100\n" +
                          seed.substr(firstEnd);
  for (const auto& [text, expected] : {std::pair<std::string, std::string>{repeated, "given twice"},
                                       {hex, "not a decimal number"}}) {
    comm->barrier();
    if (comm->getRank() == 0) std::ofstream(K, std::ios::binary | std::ios::trunc) << text;
    comm->barrier();
    std::string what;
    try {
      Substructure::fromMatrixMarket(dir + "/twice.cms", comm);
    } catch (const InputError& err) {
      what = err.what();
    }
    EXPECT_NE(what.find(K), std::string::npos) << what;
    EXPECT_NE(what.find(expected), std::string::npos) << what;
  }
}

// A general file's triangles must mirror each other: M, K, KT1 and KS1
// symmetric, G1 skew-symmetric. The symmetric solvers read one triangle, so
// an asymmetric K was read and solved as another matrix, silently (a
// review). Windows line endings got Tpetra's message about the banner's
// symmetry word. Each refused naming the file and line, on every rank (so
// are a skew G1's nonzero diagonal and a banner that contradicts the
// matrix); a matrix printed to 8 significant digits (1e-8 apart) is read.
TEST(MatrixMarketFile, AsymmetricMatricesAndWindowsLineEndingsAreRefused) {
  const auto comm = world();
  const std::string dir = writtenBeam("mirror", true);
  const std::string K = dir + "/mirror_K.mtx", G = dir + "/mirror_G1.mtx";
  const std::string seedK = slurp(K), seedG = slurp(G);
  // The first off-diagonal entry of a file, its value scaled by `factor`.
  auto scaled = [](const std::string& seed, double factor) {
    std::istringstream in(seed);
    std::ostringstream out;
    std::string line;
    bool sized = false, done = false;
    while (std::getline(in, line)) {
      if (!done && sized && line[0] != '%') {
        std::istringstream e(line);
        long long i = 0, j = 0;
        double v = 0.0;
        e >> i >> j >> v;
        if (i != j && v != 0.0) {
          std::ostringstream w;
          w << i << " " << j << " " << std::setprecision(17) << v * factor;
          line = w.str(), done = true;
        }
      } else if (line[0] != '%') {
        sized = true;
      }
      out << line << "\n";
    }
    return out.str();
  };
  // The banner's symmetry word replaced, and G1's (1, 1) entry (a written zero) set.
  auto banner = [](const std::string& seed, const std::string& word) {
    const std::size_t eol = seed.find('\n');
    return "%%MatrixMarket matrix coordinate real " + word + seed.substr(eol);
  };
  auto diagonal = [](const std::string& seed) {
    const std::size_t at = seed.find("\n1 1 ");  // written, as zero, by the framework's writer
    const std::size_t eol = seed.find('\n', at + 1);
    return seed.substr(0, at) + "\n1 1 2.5" + seed.substr(eol);
  };
  auto crlf = [](const std::string& seed) {
    std::string out;
    for (char c : seed) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
    return out;
  };
  struct Case {
    std::string file, text, expected;  // expected "": read
  };
  const std::vector<Case> cases = {{K, scaled(seedK, 1.01), "K must be symmetric, but entry ("},
                                   {K, scaled(seedK, 1.0 + 1e-8), ""},
                                   {G, scaled(seedG, -1.0), "G1 must be skew-symmetric, but entry ("},
                                   {G, diagonal(seedG), "G1 must be skew-symmetric, but its diagonal entry (1, 1)"},
                                   {K, banner(seedK, "skew-symmetric"), "K is symmetric; the banner says skew-symmetric"},
                                   {G, banner(seedG, "symmetric"), "G1 is skew-symmetric; the banner says symmetric"},
                                   {K, crlf(seedK), "Windows line endings (CRLF)"}};
  for (const auto& c : cases) {
    comm->barrier();
    if (comm->getRank() == 0) {
      std::ofstream(K, std::ios::binary | std::ios::trunc) << seedK;
      std::ofstream(G, std::ios::binary | std::ios::trunc) << seedG;
      std::ofstream(c.file, std::ios::binary | std::ios::trunc) << c.text;
    }
    comm->barrier();
    std::string what = "(read)";
    try {
      Substructure::fromMatrixMarket(dir + "/mirror.cms", comm);
    } catch (const InputError& err) {
      what = err.what();
    }
    if (c.expected.empty()) {
      EXPECT_EQ(what, "(read)");
    } else {
      EXPECT_NE(what.find(c.file + ":"), std::string::npos) << what;
      EXPECT_NE(what.find(c.expected), std::string::npos) << what;
    }
  }
}
