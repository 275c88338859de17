// The process's heap on transparent huge pages (doc/architecture.md, "The
// heap on huge pages"). Kept apart from Program.hpp so that what calls it
// first thing in main needs no Trilinos header.
#pragma once

#include <string>
#include <vector>

namespace cms {

/// First thing in main: the process's heap on transparent huge pages, its
/// freed blocks kept for reuse.
///
/// Huge pages. glibc (>= 2.35) advises its heap and mmap'd blocks as huge-page
/// candidates when GLIBC_TUNABLES holds glibc.malloc.hugetlb=1, and reads
/// its tunables only when a process starts; so a process started without it
/// executes itself again (execv of /proc/self/exe: the same PID, arguments
/// and environment, plus the tunable) before it has done anything. On this
/// project's 2-core virtual machine a page fault costs microseconds: the
/// 54,000-DOF bar's `cms modes` took 276,000 of them and 9.2 s, with the
/// tunable 11,000 and 6.1 s, at the same peak memory (doc/benchmarks.md,
/// "The heap on huge pages"); the second start costs ~40 ms there, which
/// an exported GLIBC_TUNABLES avoids. Skipped (see hugePageHeapSkipped) with
/// CMS_HUGE_PAGES=0, without THP, under valgrind, or with an older glibc; a
/// GLIBC_TUNABLES that already names the tunable is left as it is, and a
/// process executed once already (CMS_HUGE_PAGES_EXECUTED in its
/// environment) is not executed again. A program that links this (any that
/// calls it) executes itself again from its .preinit_array, before the
/// shared libraries' initialisers run; the call in main is then a no-op
/// kept for programs whose loader ignores .preinit_array.
///
/// Freed blocks kept. glibc returns a freed block of more than its mmap
/// threshold (128 KiB at first, raised to the largest block freed, at most
/// 32 MiB) to the kernel at once, so the next block of that size is fresh
/// memory that faults and is zeroed again. A run assembles, copies and
/// frees matrices of tens of MiB one after another: the 9,702-DOF Hex64 bar
/// spent a fifth of its time zeroing fresh pages. Here blocks up to
/// kKeptBlockBytes come from the heap, and its top is trimmed only past
/// twice that: 1.47 s to 1.39 s on that bar, 63.0 s to 56.8 s on the
/// 5.7e5-DOF rotor at the same peak (doc/benchmarks.md, "Fewer sparse
/// products, one start, freed blocks kept"). Larger blocks (a big model's
/// factors) still go back to the kernel when freed. Kept blocks that a
/// later, larger one cannot use add to the peak: the 1.3e5-DOF rotor's rose
/// 2% (861 to 879 MiB). Skipped (freedBlocksKeptSkipped) with CMS_KEEP_FREED=0
/// or a GLIBC_TUNABLES that sets glibc.malloc.mmap_threshold or
/// trim_threshold itself.
void hugePageHeap(char** argv);

/// The largest block the heap keeps for reuse when it is freed: 256 MiB.
inline constexpr long kKeptBlockBytes = 256L << 20;

/// Why hugePageHeap would not keep freed blocks ("" if it would, or did).
std::string freedBlocksKeptSkipped();

/// Why hugePageHeap would not re-execute this process ("" if it would, or
/// did).
std::string hugePageHeapSkipped();

/// The same for a process started with the environment block `envp`.
std::string hugePageHeapSkippedIn(char** envp);

/// An environment block for execve: pointers into the one it was made from
/// and into the two strings held here.
struct HugePageEnvironment {
  std::string tunables, marker;
  std::vector<char*> block;
};

/// Whether a process started with `envp` should be started with the heap's
/// tunable instead, and if so that environment in `out`: `envp` with
/// glibc.malloc.hugetlb=1 added to GLIBC_TUNABLES and the marker
/// CMS_HUGE_PAGES_EXECUTED=1. False when GLIBC_TUNABLES names the tunable
/// already, the marker is there, or hugePageHeapSkippedIn gives a reason.
/// libc only (HugePageEnvironment.cpp): what the cms launcher uses to start
/// the engine once, with the tunable (drivers/cms/launcher.cpp).
bool withHugePageTunable(char** envp, HugePageEnvironment& out);

}  // namespace cms
