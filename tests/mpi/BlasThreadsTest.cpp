// The BLAS's own threads (cms/core/BlasThreads.hpp): a scope sets and
// restores them, and each rank gets its share of the node's cores unless the
// environment chose. Where the BLAS has no threads of its own (the reference
// BLAS), only the no-op behaviour is checked.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

#if defined(__linux__)
#include <sched.h>
#endif

#include <Teuchos_DefaultComm.hpp>

#include "cms/core/BlasThreads.hpp"

using namespace cms;

namespace {
bool controllable() {
  const int before = blasThreads();
  const bool ok = setBlasThreads(before);
  return ok && blasThreads() == before;
}
}  // namespace

TEST(BlasThreads, AScopeSetsAndRestoresTheCount) {
  if (!controllable()) {
    EXPECT_EQ(blasThreads(), 1);
    EXPECT_FALSE(setBlasThreads(2));
    GTEST_SKIP() << "this BLAS has no threads of its own";
  }
  ASSERT_TRUE(setBlasThreads(3));
  ASSERT_EQ(blasThreads(), 3);
  {
    const BlasThreadScope one(1);
    EXPECT_EQ(blasThreads(), 1);
    {
      const BlasThreadScope two(2);
      EXPECT_EQ(blasThreads(), 2);
    }
    EXPECT_EQ(blasThreads(), 1);
  }
  EXPECT_EQ(blasThreads(), 3);
  EXPECT_FALSE(setBlasThreads(0)) << "0 threads is refused, not passed on";
  EXPECT_EQ(blasThreads(), 3);
}

// Each rank's share: the hardware threads over the ranks on the node (all
// ranks of this test are on one machine), at most the cores it is bound
// to, at least 1; left alone when the
// environment names a count (the test environment sets
// OPENBLAS_NUM_THREADS=1, which is put back after).
TEST(BlasThreads, EachRankGetsItsShareOfTheNodesCores) {
  if (!controllable()) GTEST_SKIP() << "this BLAS has no threads of its own";
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const char* saved = std::getenv("OPENBLAS_NUM_THREADS");
  const std::string value = saved ? saved : "";
  unsetenv("OPENBLAS_NUM_THREADS");
  unsetenv("GOTO_NUM_THREADS");
  const char* omp = std::getenv("OMP_NUM_THREADS");
  const std::string ompValue = omp ? omp : "";
  unsetenv("OMP_NUM_THREADS");
  setBlasThreads(7);
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int share = std::max(1, std::min(usableCores(), cores / ranks));
  EXPECT_EQ(shareCoresWithBlas(*Teuchos::DefaultComm<int>::getComm()), share);
  EXPECT_EQ(blasThreads(), share);

  setenv("OPENBLAS_NUM_THREADS", "1", 1);
  setBlasThreads(5);
  EXPECT_EQ(shareCoresWithBlas(*Teuchos::DefaultComm<int>::getComm()), 5) << "the environment's choice is left alone";
  if (saved) setenv("OPENBLAS_NUM_THREADS", value.c_str(), 1);
  else unsetenv("OPENBLAS_NUM_THREADS");
  if (omp) setenv("OMP_NUM_THREADS", ompValue.c_str(), 1);
  setBlasThreads(1);
}

// A rank bound to one core (as mpiexec binds a lone rank by default) gets
// one BLAS thread, not the node's share: two threads on one core ran the
// 1.3e5-DOF rotor's reduction 1.3x slower than one process unbound
// (doc/benchmarks.md, "A lone rank under mpiexec").
TEST(BlasThreads, ARankBoundToOneCoreGetsOneThread) {
#if defined(__linux__)
  if (!controllable()) GTEST_SKIP() << "this BLAS has no threads of its own";
  cpu_set_t saved, one;
  ASSERT_EQ(sched_getaffinity(0, sizeof(saved), &saved), 0);
  int first = 0;
  while (first < CPU_SETSIZE && !CPU_ISSET(first, &saved)) ++first;
  ASSERT_LT(first, CPU_SETSIZE);
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  EXPECT_EQ(usableCores(), 1);
  EXPECT_EQ(coresPerRank(1), 1);
  const char* env = std::getenv("OPENBLAS_NUM_THREADS");
  const std::string value = env ? env : "";
  unsetenv("OPENBLAS_NUM_THREADS");
  const char* omp = std::getenv("OMP_NUM_THREADS");
  const std::string ompValue = omp ? omp : "";
  unsetenv("OMP_NUM_THREADS");
  setBlasThreads(4);
  EXPECT_EQ(shareCoresWithBlas(*Teuchos::DefaultComm<int>::getComm()), 1);
  if (env) setenv("OPENBLAS_NUM_THREADS", value.c_str(), 1);
  if (omp) setenv("OMP_NUM_THREADS", ompValue.c_str(), 1);
  ASSERT_EQ(sched_setaffinity(0, sizeof(saved), &saved), 0);
  EXPECT_EQ(usableCores(), std::max(1, std::min(static_cast<int>(std::thread::hardware_concurrency()), CPU_COUNT(&saved))));
  setBlasThreads(1);
#else
  GTEST_SKIP() << "CPU affinity is read on Linux only";
#endif
}
