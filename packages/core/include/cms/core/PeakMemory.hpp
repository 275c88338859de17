// The process's peak memory, for the drivers' and studies' reports, and the
// memory it may still use, for the checks that refuse a run that cannot fit
// (Linux).
#pragma once

#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

#include <sys/resource.h>

#include <algorithm>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

namespace cms {

namespace detail {
/// A "kB" field of /proc/self/status in bytes (0 where absent).
inline double statusBytes(const char* field) {
  std::ifstream f("/proc/self/status");
  const std::string key = std::string(field) + ":";
  for (std::string line; std::getline(f, line);)
    if (line.rfind(key, 0) == 0) return 1024.0 * std::strtod(line.c_str() + key.size(), nullptr);
  return 0.0;
}
}  // namespace detail

/// Memory this process may still use (bytes): the least of MemAvailable in
/// /proc/meminfo, what the address-space limit (ulimit -v) leaves above the
/// process's mapped size (VmSize), what the cgroup's memory.max leaves above
/// its memory.current (less its inactive file cache, which the kernel
/// reclaims first), and the environment's CMS_MEMORY_LIMIT (bytes, e.g. 8e9:
/// a budget on a shared machine); infinity when none is known. (The two
/// limits were taken whole, as if nothing were in use: in a container,
/// where /proc/meminfo shows the host, the guards then let through what the
/// out-of-memory killer ended; found by a review.)
inline double availableMemoryBytes() {
  double bytes = std::numeric_limits<double>::infinity();
  if (const char* limit = std::getenv("CMS_MEMORY_LIMIT")) {
    char* end = nullptr;
    const double v = std::strtod(limit, &end);
    if (end != limit && v > 0) bytes = v;
  }
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    double kib = 0;
    if (key == "MemAvailable:" && meminfo >> kib) bytes = std::min(bytes, 1024.0 * kib);
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    bytes = std::min(bytes, std::max(0.0, static_cast<double>(as.rlim_cur) - detail::statusBytes("VmSize")));
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");
  double max = 0;
  if (cgroup >> max && max > 0) {  // "max" (no limit) does not read as a number
    double current = 0, inactiveFile = 0;
    std::ifstream("/sys/fs/cgroup/memory.current") >> current;
    std::ifstream stat("/sys/fs/cgroup/memory.stat");
    for (std::string key; stat >> key;) {
      double v = 0;
      if (key == "inactive_file" && stat >> v) inactiveFile = v;
      stat.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    bytes = std::min(bytes, std::max(0.0, max - std::max(0.0, current - inactiveFile)));
  }
  return bytes;
}

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
