#include "cms/core/BlasThreads.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "cms/core/DistributedDirectSolver.hpp"

namespace cms {

namespace {

// OpenBLAS's controls, looked up in the process (the BLAS cms linked is
// whichever Debian alternative libblas.so.3 points to).
using SetThreads = void (*)(int);
using GetThreads = int (*)();

SetThreads setter() {
  static const auto f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  return f;
}
GetThreads getter() {
  static const auto f = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return f;
}
/// Ends OpenBLAS's pool of worker threads; its next threaded call starts
/// the pool again (exec_blas: "lazy re-init", as after a fork).
using Shutdown = int (*)();
Shutdown shutdown() {
  static const auto f = reinterpret_cast<Shutdown>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"));
  return f;
}

}  // namespace

int blasThreads() { return getter() != nullptr ? std::max(1, getter()()) : 1; }

bool setBlasThreads(int n) {
  if (setter() == nullptr || n < 1) return false;
  setter()(n);
  return true;
}

BlasThreadScope::BlasThreadScope(int n) : previous_(blasThreads()) {
  setBlasThreads(n);
  // Fewer threads leave the pool's idle workers spinning in sched_yield
  // for OpenBLAS's thread timeout (~0.27 s after each threaded call) beside
  // cms's own threads: on the spacecraft's 101-speed sweep one such worker
  // took ~25% of the samples. With one thread, none is needed: end them.
  if (n == 1 && previous_ > 1 && shutdown() != nullptr) shutdown()();
}

BlasThreadScope::~BlasThreadScope() { setBlasThreads(previous_); }

int shareCoresWithBlas(const Teuchos::Comm<int>& comm) {
  const int onNode = ranksOnNode(comm);  // collective: before any rank returns
  for (const char* chosen : {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
    if (std::getenv(chosen) != nullptr) return blasThreads();
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  setBlasThreads(std::max(1, cores / std::max(1, onNode)));
  return blasThreads();
}

}  // namespace cms
