// The memory the process may still use (cms/core/PeakMemory.hpp), which
// every out-of-memory guard holds a factorisation or a count against.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstring>
#include <string>

#include "LimitedChild.hpp"
#include "cms/core/PeakMemory.hpp"

TEST(PeakMemory, AnAddressSpaceLimitLeavesOnlyWhatIsNotMappedYet) {
  // ulimit -v at the mapped size plus 64 MiB: what is left is about 64 MiB,
  // not the whole limit (taken whole, as if nothing were mapped, the guards
  // let through what could not fit; found by a review). The process maps a
  // little more while it reads /proc (the streams' buffers): 8 MiB of slack.
  // In a forked child: the limit binds the whole process, and in the test
  // process itself it would bind the BLAS's or MPI's threads too, for as
  // long as it is set.
  const double room = 64.0 * 1024 * 1024;
  rlimit hard{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &hard), 0);
  const auto child = cms::fixtures::forkLimited(hard.rlim_max, [room](int fd) {
    double out[2] = {-1.0, -1.0};
    rlimit tight{};
    out[0] = cms::detail::statusBytes("VmSize");
    if (getrlimit(RLIMIT_AS, &tight) == 0 && out[0] > 0.0) {
      tight.rlim_cur = static_cast<rlim_t>(out[0] + room);
      if (tight.rlim_max == RLIM_INFINITY || tight.rlim_cur <= tight.rlim_max) {
        if (setrlimit(RLIMIT_AS, &tight) == 0) out[1] = cms::availableMemoryBytes();
      } else {
        out[1] = -2.0;  // the hard limit is below: nothing to test
      }
    }
    cms::fixtures::writeAll(fd, std::string(reinterpret_cast<const char*>(out), sizeof out));
  });
  std::string got;
  const int status = cms::fixtures::finish(child, [&](const char* p, std::size_t n) { got.append(p, n); });
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child did not exit cleanly";
  ASSERT_EQ(got.size(), 2 * sizeof(double));
  double out[2];
  std::memcpy(out, got.data(), sizeof out);
  if (out[1] == -2.0) GTEST_SKIP() << "hard limit below";
  ASSERT_GT(out[0], 0.0) << "VmSize not readable";
  const double left = out[1];
  EXPECT_LE(left, room);
  EXPECT_GE(left, room - 8.0 * 1024 * 1024);
}
