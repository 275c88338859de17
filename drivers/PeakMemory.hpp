// The process's peak resident memory, for the benchmark drivers' reports.
#pragma once

#include <sys/resource.h>

namespace cms::drivers {

/// Maximum resident set size of this process so far, in MiB (Linux reports KiB).
inline double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

}  // namespace cms::drivers
