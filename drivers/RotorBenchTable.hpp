// bench_rotor's table (drivers/bench_rotor.cpp): one row per measurement,
// its CSV columns (read by `plot_results.py rotor` and quoted in
// doc/benchmarks.md, so they stay as they are) and its console line.
#pragma once

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <string>
#include <vector>

#include "cms/core/PeakMemory.hpp"
#include "cms/io/OutputFiles.hpp"

namespace cms::drivers {

/// One row: a measurement at one mesh size (what: assembly, floor, truth,
/// reduced, distributed-schedule or sweep). Seconds are wall times; errors
/// -1 where nothing was compared.
struct Row {
  double h = 0;
  long long physicalDofs = 0, truthDofs = 0;
  std::string what, strategy;
  int vectors = 0;
  long long reducedDofs = 0;
  double assembly = 0, reduce = 0, synth = 0, solve = 0, pipeline = 0, truth = 0, floor = 0, fullMiB = 0;
  PeakMemoryWindow::Peak mem;
  double maxError = -1, meanError = -1, worstMac = -1;
  std::string note;
  std::vector<double> hz;  ///< the lowest frequencies (for comparisons across runs)

  /// This row (of a size: what its rows share) as another measurement.
  Row with(const char* w, const std::string& s) const {
    Row r = *this;
    r.what = w, r.strategy = s;
    return r;
  }
};

/// The whole table, written anew (rank 0; through a temporary file).
inline void writeCsv(const std::string& path, const std::vector<Row>& rows, int ranks) {
  io::OutputFiles file;
  auto& os = file.open(path);
  os << "h,physical_dofs,truth_dofs,ranks,what,strategy,vectors,reduced_dofs,assembly_s,reduce_s,synthesis_s,solve_s,"
        "pipeline_s,truth_s,floor_s,pipeline_over_truth,pipeline_over_floor,peak_mib_max_rank,peak_mib_sum,"
        "resident_at_start_mib,full_k_m_factor_mib,max_rel_error,mean_rel_error,worst_mac,note,frequencies_hz\n";
  auto ratio = [](double a, double b) { return a > 0 && b > 0 ? a / b : 0.0; };
  for (Row r : rows) {
    std::replace_if(r.note.begin(), r.note.end(), [](char c) { return c == ',' || c == '\n'; }, ';');
    os << r.h << ',' << r.physicalDofs << ',' << r.truthDofs << ',' << ranks << ',' << r.what << ',' << r.strategy
       << ',' << r.vectors << ',' << r.reducedDofs << ',' << r.assembly << ',' << r.reduce << ',' << r.synth << ','
       << r.solve << ',' << r.pipeline << ',' << r.truth << ',' << r.floor << ',' << ratio(r.pipeline, r.truth) << ','
       << ratio(r.pipeline, r.floor) << ',' << r.mem.max << ',' << r.mem.sum << ',' << r.mem.base << ',' << r.fullMiB
       << ',' << r.maxError << ',' << r.meanError << ',' << r.worstMac << ',' << r.note << ',' << std::setprecision(15);
    for (std::size_t i = 0; i < r.hz.size(); ++i) os << (i ? ";" : "") << r.hz[i];
    os << std::setprecision(6) << '\n';
  }
  file.commit();
}

/// The console line of a row.
inline void printRow(std::ostream& os, const Row& r) {
  os << std::left << std::setw(21) << r.what << std::setw(14) << r.strategy << std::right << std::setw(3) << r.vectors
     << std::setw(8) << r.reducedDofs << " coords " << std::setprecision(3) << std::setw(9)
     << (r.what == "floor" ? r.floor : r.pipeline) << " s (bases " << r.reduce << ", synth " << r.synth << ", solve "
     << r.solve << "); max err " << r.maxError << "; peak " << std::setprecision(5) << r.mem.max << " MiB; " << r.note
     << std::setprecision(6) << '\n';
}

}  // namespace cms::drivers
