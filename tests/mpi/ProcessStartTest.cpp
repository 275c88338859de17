// A process started without a launcher (cms/core/Program.hpp,
// singletonMpiDefaults, called by MpiGTestMain before MPI starts): MPI's
// defaults for a lone process (no daemon, only the MPI components one
// process uses), and hwloc's device plugins left unloaded
// (they bring libX11, libOpenCL, libxml2 and ICU into every start), nor its
// reading of every PCI, block and network device in /sys (18 ms). Run
// without mpiexec by the test process_start_singleton; under a launcher
// the environment is left to it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include <hwloc.h>

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

namespace {
/// PCI and OS devices in a topology hwloc loads now, asked to keep every one.
int devicesFound() {
  hwloc_topology_t topology;
  if (hwloc_topology_init(&topology) != 0) return -1;
  hwloc_topology_set_io_types_filter(topology, HWLOC_TYPE_FILTER_KEEP_ALL);
  int n = -1;
  if (hwloc_topology_load(topology) == 0)
    n = hwloc_get_nbobjs_by_type(topology, HWLOC_OBJ_PCI_DEVICE) + hwloc_get_nbobjs_by_type(topology, HWLOC_OBJ_OS_DEVICE);
  hwloc_topology_destroy(topology);
  return n;
}
}  // namespace

TEST(ProcessStart, ALoneProcessLeavesHwlocsDeviceDiscoveryOut) {
  if (launched()) GTEST_SKIP() << "started by a launcher: its environment is left as it is";
  const char* components = std::getenv("HWLOC_COMPONENTS");
  ASSERT_NE(components, nullptr);
  // hwloc reads HWLOC_COMPONENTS at every load, as Open MPI's load read it.
  EXPECT_EQ(devicesFound(), 0) << "HWLOC_COMPONENTS=" << components;
  // The control: the same load without the setting finds this machine's
  // devices (where /sys shows any: otherwise the check above is vacuous here).
  const std::string kept(components);
  unsetenv("HWLOC_COMPONENTS");
  const int withDiscovery = devicesFound();
  setenv("HWLOC_COMPONENTS", kept.c_str(), 1);
  EXPECT_GE(withDiscovery, 0);
  if (withDiscovery == 0) std::cout << "note: hwloc finds no PCI or OS device on this machine even with discovery\n";
  else std::cout << "hwloc's device discovery finds " << withDiscovery << " PCI and OS devices here\n";
}
