// Wall-clock seconds for the timings every result reports (synthesis,
// solves, studies, benchmarks): one steady clock, one conversion.
#pragma once

#include <chrono>

namespace cms {

class Stopwatch {
public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  /// Seconds since construction or the last restart().
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace cms
