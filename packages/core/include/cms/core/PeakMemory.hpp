// The process's peak memory, for the drivers' and studies' reports (Linux).
#pragma once

#include <fstream>
#include <string>

#include <sys/resource.h>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

namespace cms {

/// Maximum resident set size of this process so far, in MiB (Linux reports KiB).
inline double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

/// Starts a new peak-memory window: Linux (>= 4.0) resets the resident
/// high-water mark VmHWM to the current resident size when "5" is written
/// to /proc/self/clear_refs. Returns false where that is not possible (the
/// window then reaches back to the process start).
inline bool resetPeakRss() {
  std::ofstream f("/proc/self/clear_refs");
  if (!f) return false;
  f << "5";
  return static_cast<bool>(f);
}

/// VmHWM: the peak resident memory since the last resetPeakRss() (MiB), or
/// peakRssMiB() where /proc is not readable.
inline double windowPeakRssMiB() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return peakRssMiB();
}

/// VmRSS: the resident memory now (MiB), 0 where /proc is not readable.
inline double residentMiB() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

/// Peak memory of a window of a run, over every rank (the benchmarks'
/// memory columns): `open()` starts the window on this rank; `peak()`
/// (collective) gives the largest rank's peak since, the sum of the ranks'
/// peaks, and the largest resident memory when the window opened: the peak
/// includes what the process already held, `base` says how much. Never
/// opened, the window reaches back to the process start.
class PeakMemoryWindow {
public:
  struct Peak {
    double max = 0.0, sum = 0.0, base = 0.0;  ///< MiB
  };
  explicit PeakMemoryWindow(const Teuchos::Comm<int>& comm) : comm_(comm) {}
  void open() {
    resetPeakRss();
    base_ = residentMiB();
  }
  Peak peak() const {
    const double mine = windowPeakRssMiB();
    Peak p;
    Teuchos::reduceAll(comm_, Teuchos::REDUCE_MAX, 1, &mine, &p.max);
    Teuchos::reduceAll(comm_, Teuchos::REDUCE_SUM, 1, &mine, &p.sum);
    Teuchos::reduceAll(comm_, Teuchos::REDUCE_MAX, 1, &base_, &p.base);
    return p;
  }

private:
  const Teuchos::Comm<int>& comm_;
  double base_ = 0.0;
};

}  // namespace cms
