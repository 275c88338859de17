// A process started without a launcher (cms/core/Program.hpp,
// singletonMpiDefaults, called by MpiGTestMain before MPI starts): MPI's
// defaults for a lone process (no daemon, only the MPI components one
// process uses), and hwloc's device plugins left unloaded
// (they bring libX11, libOpenCL, libxml2 and ICU into every start). Run
// without mpiexec by the test process_start_singleton; under a launcher
// the environment is left to it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace {
bool launched() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "SLURM_PROCID"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}
}  // namespace

TEST(ProcessStart, ALoneProcessMapsNoDevicePluginOfHwloc) {
  if (launched()) GTEST_SKIP() << "started by a launcher: its environment is left as it is";
  ASSERT_NE(std::getenv("HWLOC_PLUGINS_BLACKLIST"), nullptr);
  ASSERT_NE(std::getenv("OMPI_MCA_ess_singleton_isolated"), nullptr);
  ASSERT_NE(std::getenv("OMPI_MCA_btl"), nullptr);  // and MPI started with it (MpiGTestMain)
  // MPI has started (MpiGTestMain), and hwloc with it: what it mapped is in
  // the process's maps. Without the blacklist hwloc_pci.so and libX11 are.
  std::ifstream maps("/proc/self/maps");
  ASSERT_TRUE(maps.good());
  std::string line;
  int lines = 0;
  while (std::getline(maps, line)) {
    ++lines;
    for (const char* plugin : {"hwloc_pci.so", "hwloc_gl.so", "hwloc_opencl.so", "hwloc_xml_libxml.so", "libX11.so",
                               "mca_btl_tcp.so", "mca_coll_tuned.so"})
      EXPECT_EQ(line.find(plugin), std::string::npos) << line;
  }
  EXPECT_GT(lines, 0);
}
