// Each reduced mode's error estimate (SynthesizedStructure::errorEstimates,
// doc/theory.md §11.8) against its true error, the reduced frequency against
// the truth model of the same structure (issue #9): within a factor 3 of the
// truth wherever the true error is above 1e-8, on the hub-boom structure
// (spinning, clamped and free), for every basis kind and count of
// doc/bench/basis-comparison.csv. CMS_WRITE_TABLE=path writes the table of
// doc/bench/error-estimates.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <Teuchos_DefaultComm.hpp>

#include "HubBoomStructure.hpp"
#include "cms/core/Error.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

using namespace cms;
using namespace cms::synthesis;

namespace {

const fixtures::HubBoom hb;

StructureModes solve(const SynthesizedStructure& s, int modes) {
  Teuchos::ParameterList p;
  p.set("Number of Modes", modes);
  return s.solve({hb.Omega}, p);
}

struct Row {
  std::string structure, basis;
  int vectors, mode;
  double truth, estimate;
};

std::vector<Row> rows(bool free) {
  const auto structure = AssembledStructure::assemble(hb.structure(free, "Full", 0), Teuchos::DefaultComm<int>::getComm());
  const auto truth = SynthesizedStructure::synthesize(structure, true);
  const int compared = 6, skip = free ? 9 : 0;  // free: past the rigid and frame-rate modes
  const auto t = solve(truth, skip + compared + 4);
  std::vector<Row> out;
  for (const std::string basis : {"Admissible", "Modes", "Craig-Bampton"})
    for (int k : {2, 4, 6, 8, 12}) {
      const auto s = SynthesizedStructure::synthesize(structure, sameReduction(structure, basis, k));
      if (s.size() < skip + compared) continue;
      const auto m = solve(s, skip + compared);
      const auto c = analysis::compareWithTruth(s, m, truth, t, skip + compared);
      const auto e = s.errorEstimates(m);
      for (int j = skip; j < skip + compared; ++j)
        out.push_back({free ? "free" : "clamped", basis, k, j + 1, std::abs(c.modes[j].relativeError), e[j]});
    }
  return out;
}

}  // namespace

TEST(ErrorEstimate, WithinAFactorThreeOfTheTrueError) {
  std::ostringstream table;
  table << "structure,basis,vectors_per_substructure,mode,true_rel_error,estimated_rel_error\n";
  int checked = 0;
  for (bool free : {false, true})
    for (const auto& r : rows(free)) {
      table << r.structure << ',' << r.basis << ',' << r.vectors << ',' << r.mode << ',' << std::setprecision(3)
            << r.truth << ',' << r.estimate << '\n';
      const std::string where = r.structure + " " + r.basis + " " + std::to_string(r.vectors) + " mode " +
                                std::to_string(r.mode);
      ASSERT_GE(r.estimate, 0.0) << where;
      // Below 1e-8 the true error is the truth solve's own rounding
      // (eta kappa, kappa up to 1e9 for the free hub's lowest modes, theory
      // §11.7), not the reduction's: not compared.
      if (r.truth <= 1e-8) continue;
      ++checked;
      // The estimate is first order in the residual: it holds while the
      // error is small. Past 10% (a mode the basis cannot represent: the
      // fifth and sixth modes with 2 vectors are 20-300 times off) it is a
      // flag, "unresolved", not a number: then the truth must be far off
      // too, and a far-off truth must be flagged (theory §11.8).
      if (r.estimate < 0.1) {
        EXPECT_LE(r.estimate, 3.0 * r.truth) << where;
        EXPECT_GE(r.estimate, r.truth / 3.0) << where;
      } else {
        EXPECT_GE(r.truth, 0.01) << where << ": flagged unresolved, but accurate";
      }
      if (r.truth >= 0.1) EXPECT_GE(r.estimate, 0.1) << where << ": unresolved, but not flagged";
    }
  EXPECT_GT(checked, 50);
  if (const char* path = std::getenv("CMS_WRITE_TABLE")) std::ofstream(path) << table.str();
}

// Missing-mode detection (theory §11.9): each substructure's Sturm count
// below a cut-off (a sparse LDL^T inertia) equals the number of its exact
// modes below it (the Ritz values of a basis of all its modes, an
// independent dense computation), and a basis too small for the cut-off is
// reported as able to miss modes.
TEST(Coverage, SturmCountMatchesTheSubstructuresOwnModes) {
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Full", 0), Teuchos::DefaultComm<int>::getComm());
  const auto all = SynthesizedStructure::synthesize(structure, sameReduction(structure, "Modes", 100000));
  const auto small = SynthesizedStructure::synthesize(structure, sameReduction(structure, "Craig-Bampton", 2));
  int missing = 0;
  for (double hz : {1.0, 10.0, 60.0, 300.0}) {
    const double w = 2 * M_PI * hz;
    const auto exact = all.coverage(w), reduced = small.coverage(w);
    ASSERT_EQ(exact.size(), reduced.size());
    for (std::size_t k = 0; k < exact.size(); ++k) {
      if (exact[k].basis == "Full" || exact[k].verdict == "rigid") continue;
      EXPECT_EQ(exact[k].sturmCount, exact[k].represented) << exact[k].name << " at " << hz << " Hz";
      EXPECT_EQ(exact[k].verdict, "complete") << exact[k].name;
      EXPECT_EQ(reduced[k].sturmCount, exact[k].sturmCount) << reduced[k].name << " at " << hz << " Hz";
      EXPECT_LE(reduced[k].represented, reduced[k].sturmCount) << "a Ritz value below its mode";
      if (reduced[k].represented < reduced[k].sturmCount) {
        ++missing;
        EXPECT_NE(reduced[k].verdict.find("can miss"), std::string::npos) << reduced[k].verdict;
      }
    }
  }
  EXPECT_GT(missing, 0) << "2 vectors must run out below 300 Hz";
}

// Reduction driven by a cut-off (theory §11.10): "Cutoff Frequency" takes
// every fixed-interface mode below it (Craig-Bampton, Modes) or grows
// admissible vectors until their Ritz estimates cover the substructure's
// modes there; each substructure's coverage at the cut-off is then complete,
// and the structure's frequencies below the cut-off are estimated accurate.
TEST(Coverage, CutoffFrequencyTakesEveryModeBelowIt) {
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Full", 0), Teuchos::DefaultComm<int>::getComm());
  for (const std::string basis : {"Craig-Bampton", "Modes", "Admissible"})
    for (double hz : {5.0, 300.0}) {
      auto reductions = sameReduction(structure, basis, 2);
      for (auto& r : reductions)
        if (r.get<std::string>("Basis") != "Full") r.set("Cutoff Frequency", hz);
      const auto s = SynthesizedStructure::synthesize(structure, reductions);
      for (const auto& c : s.coverage(2 * M_PI * hz))
        if (c.basis != "Full" && c.verdict != "rigid")
          EXPECT_EQ(c.verdict, "complete") << basis << " " << hz << " Hz: " << c.name << " " << c.verdict;
    }
  // Without it, 2 vectors run short at 300 Hz: the cut-off did the work.
  bool short2 = false;
  for (const auto& c : SynthesizedStructure::synthesize(structure, sameReduction(structure, "Craig-Bampton", 2))
                           .coverage(2 * M_PI * 300.0))
    short2 = short2 || c.verdict.find("can miss") != std::string::npos;
  EXPECT_TRUE(short2);
  // A cut-off that is not a frequency is bad input naming the key.
  auto bad = sameReduction(structure, "Craig-Bampton", 2);
  bad[1].set("Cutoff Frequency", -1.0);
  EXPECT_THROW(SynthesizedStructure::synthesize(structure, bad), InputError);
}

// --check-count's structure-level count (analysis::truthFrequenciesBelow,
// one LDL^T of the assembled K - w^2 M + i w G) equals the number of the
// truth's frequencies below w from its dense gyroscopic solve, between and
// around its (spinning) frequencies.
TEST(Coverage, TruthSturmCountMatchesTheTruthSolve) {
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Full", 0), Teuchos::DefaultComm<int>::getComm());
  const auto truth = SynthesizedStructure::synthesize(structure, true);
  const auto t = solve(truth, 16);
  std::vector<double> w;
  for (const auto& m : t.result.modes) w.push_back(m.omega);
  for (std::size_t j = 0; j + 1 < w.size(); ++j) {
    if (w[j + 1] - w[j] < 1e-6 * w[j + 1]) continue;  // inside a (near) repeated pair
    const double cut = 0.5 * (w[j] + w[j + 1]);
    EXPECT_EQ(analysis::truthFrequenciesBelow(structure, {hb.Omega}, cut), static_cast<long long>(j + 1))
        << "cut " << cut << " rad/s";
  }
}
