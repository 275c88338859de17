// GoogleTest main for MPI tests: initialises MPI and Kokkos through Tpetra,
// prints only rank 0's listener output, and min-reduces pass/fail across
// ranks so no rank disagrees silently (doc/architecture.md, "Tests").
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>

#include <Tpetra_Core.hpp>
#include "cms/core/Program.hpp"

namespace {
class RankFailurePrinter : public ::testing::EmptyTestEventListener {
public:
  explicit RankFailurePrinter(int rank) : rank_(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& r) override {
    if (r.failed())
      std::printf("[rank %d] %s:%d: Failure\n%s\n", rank_, r.file_name() ? r.file_name() : "?",
                  r.line_number(), r.summary());
  }

private:
  int rank_;
};
}  // namespace

int main(int argc, char** argv) {
  cms::hugePageHeap(argv);      // the heap on transparent huge pages (re-executes once)
  cms::singletonMpiDefaults();  // a lone process: no daemon, no fabric probing
  Tpetra::ScopeGuard scope(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) {  // quiet, except for its own failures
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new RankFailurePrinter(rank));
  }
  int ok = RUN_ALL_TESTS() == 0 ? 1 : 0, allOk = 0;
  MPI_Allreduce(&ok, &allOk, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return allOk ? 0 : 1;
}
