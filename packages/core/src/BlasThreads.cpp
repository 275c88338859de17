#include "cms/core/BlasThreads.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

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

int shareCoresWithBlas(MPI_Comm comm) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int onNode = 1;
  MPI_Comm_size(node, &onNode);
  MPI_Comm_free(&node);
  for (const char* chosen : {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
    if (std::getenv(chosen) != nullptr) return blasThreads();
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  setBlasThreads(std::max(1, cores / std::max(1, onNode)));
  return blasThreads();
}

}  // namespace cms
