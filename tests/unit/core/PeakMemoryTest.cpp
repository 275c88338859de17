// The memory the process may still use (cms/core/PeakMemory.hpp), which
// every out-of-memory guard holds a factorisation or a count against.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include "cms/core/PeakMemory.hpp"

TEST(PeakMemory, AnAddressSpaceLimitLeavesOnlyWhatIsNotMappedYet) {
  // ulimit -v at the mapped size plus 64 MiB: what is left is about 64 MiB,
  // not the whole limit (taken whole, as if nothing were mapped, the guards
  // let through what could not fit; found by a review). The process maps a
  // little more while it reads /proc (the streams' buffers): 8 MiB of slack.
  rlimit before{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &before), 0);
  const double mapped = cms::detail::statusBytes("VmSize"), room = 64.0 * 1024 * 1024;
  ASSERT_GT(mapped, 0.0);
  rlimit tight = before;
  tight.rlim_cur = static_cast<rlim_t>(mapped + room);
  if (before.rlim_max != RLIM_INFINITY && tight.rlim_cur > before.rlim_max) GTEST_SKIP() << "hard limit below";
  ASSERT_EQ(setrlimit(RLIMIT_AS, &tight), 0);
  const double left = cms::availableMemoryBytes();
  ASSERT_EQ(setrlimit(RLIMIT_AS, &before), 0);
  EXPECT_LE(left, room);
  EXPECT_GE(left, room - 8.0 * 1024 * 1024);
}
