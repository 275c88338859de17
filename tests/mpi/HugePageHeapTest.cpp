// The heap on transparent huge pages (cms/core/HugePageHeap.hpp):
// every cms process, this test's included (MpiGTestMain calls it first),
// runs with glibc.malloc.hugetlb in GLIBC_TUNABLES unless a stated reason
// skips it, and CMS_HUGE_PAGES=0 is such a reason. That the re-executed
// process keeps its arguments is checked by every driver test (their
// options and scene paths arrive).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>

#if defined(__linux__) && defined(__GLIBC__)
#include <malloc.h>
#endif

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

// A block above glibc's own mmap ceiling (32 MiB) and below the kept size
// comes from the heap, not from a mapping of its own that its free would
// give back to the kernel: mallinfo2's bytes in mapped blocks do not grow.
// Without hugePageHeap's thresholds glibc maps a 64 MiB block (checked with
// CMS_KEEP_FREED=0: hblkhd grows by the block).
TEST(HugePageHeap, FreedBlocksUpToTheKeptSizeComeFromTheHeap) {
#if defined(__linux__) && defined(__GLIBC__)
  const std::string skipped = freedBlocksKeptSkipped();
  if (!skipped.empty()) GTEST_SKIP() << "skipped: " << skipped;
  static_assert(kKeptBlockBytes > (64L << 20), "the block below must be within the kept size");
  const std::size_t bytes = 64UL << 20;
  const std::size_t mappedBefore = mallinfo2().hblkhd;
  void* volatile block = std::malloc(bytes);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, 4096);
  const std::size_t mappedWith = mallinfo2().hblkhd;
  std::free(block);
  EXPECT_LT(mappedWith, mappedBefore + bytes) << "a 64 MiB block was mapped on its own (freed, it goes back "
                                                 "to the kernel)";
#else
  GTEST_SKIP() << "not Linux with glibc";
#endif
}

TEST(HugePageHeap, CmsKeepFreedZeroOrTheUsersThresholdsSkipIt) {
#if defined(__linux__) && defined(__GLIBC__)
  auto skippedWith = [](const char* name, const char* value) {
    const char* before = std::getenv(name);
    const std::string saved = before != nullptr ? before : "";
    setenv(name, value, 1);
    const std::string skipped = freedBlocksKeptSkipped();
    if (before != nullptr) setenv(name, saved.c_str(), 1);
    else unsetenv(name);
    return skipped;
  };
  EXPECT_EQ(skippedWith("CMS_KEEP_FREED", "0"), "CMS_KEEP_FREED=0");
  EXPECT_EQ(skippedWith("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=65536"),
            "GLIBC_TUNABLES sets the thresholds");
  EXPECT_EQ(skippedWith("GLIBC_TUNABLES", "glibc.malloc.trim_threshold=65536"), "GLIBC_TUNABLES sets the thresholds");
#else
  EXPECT_FALSE(freedBlocksKeptSkipped().empty());
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
