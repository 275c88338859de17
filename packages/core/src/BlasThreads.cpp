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

}  // namespace

int blasThreads() { return getter() != nullptr ? std::max(1, getter()()) : 1; }

bool setBlasThreads(int n) {
  if (setter() == nullptr || n < 1) return false;
  setter()(n);
  return true;
}

BlasThreadScope::BlasThreadScope(int n) : previous_(blasThreads()) { setBlasThreads(n); }

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
