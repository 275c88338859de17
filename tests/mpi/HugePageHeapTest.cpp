// The heap on transparent huge pages (cms/core/HugePageHeap.hpp):
// every cms process, this test's included (MpiGTestMain calls it first),
// runs with glibc.malloc.hugetlb in GLIBC_TUNABLES unless a stated reason
// skips it, and CMS_HUGE_PAGES=0 is such a reason. That the re-executed
// process keeps its arguments is checked by every driver test (their
// options and scene paths arrive).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "cms/core/HugePageHeap.hpp"

using namespace cms;

TEST(HugePageHeap, TheProcessRunsWithTheTunableUnlessAReasonSkipsIt) {
  const std::string skipped = hugePageHeapSkipped();
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (!skipped.empty()) GTEST_SKIP() << "skipped: " << skipped;
  ASSERT_NE(tunables, nullptr);
  EXPECT_NE(std::string(tunables).find("glibc.malloc.hugetlb"), std::string::npos) << tunables;
}

TEST(HugePageHeap, CmsHugePagesZeroSkipsIt) {
  const char* before = std::getenv("CMS_HUGE_PAGES");
  const std::string saved = before != nullptr ? before : "";
  setenv("CMS_HUGE_PAGES", "0", 1);
  const std::string skipped = hugePageHeapSkipped();
  if (before != nullptr) setenv("CMS_HUGE_PAGES", saved.c_str(), 1);
  else unsetenv("CMS_HUGE_PAGES");
#if defined(__linux__) && defined(__GLIBC__)
  EXPECT_EQ(skipped, "CMS_HUGE_PAGES=0");
#else
  EXPECT_FALSE(skipped.empty());
#endif
}

// Run by the test hugepages_executed_once with CMS_HUGE_PAGES_EXECUTED=1 and
// GLIBC_TUNABLES unset (skipped elsewhere): a process marked as executed once
// already is not executed again, the guard against a loader that drops
// GLIBC_TUNABLES, which would otherwise execute the process for ever. Without
// the guard this process would have been executed again with the tunable.
TEST(HugePageHeap, AProcessMarkedAsExecutedIsNotExecutedAgain) {
  if (std::getenv("CMS_EXPECT_NO_REEXECUTION") == nullptr) GTEST_SKIP() << "run by the test hugepages_executed_once";
  ASSERT_NE(std::getenv("CMS_HUGE_PAGES_EXECUTED"), nullptr);
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  EXPECT_TRUE(tunables == nullptr || std::string(tunables).find("glibc.malloc.hugetlb") == std::string::npos)
      << tunables;
}
