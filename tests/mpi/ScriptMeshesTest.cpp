// The scene's .geo scripts made ahead (mesh/ScriptMeshes.hpp): each distinct
// script meshed on one rank only, side by side, its .msh sent to every rank,
// which reads the same mesh readMesh reads (node for node, group for group)
// or throws the same cms::InputError; a request taken out of order, twice,
// or not at all; a script still running when the scene is refused is
// stopped. Run on 1, 2 and 3 ranks (three scripts: one each, or several on
// one rank's threads).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <optional>
#include <pthread.h>
#include <system_error>
#include <string>
#include <thread>
#include <vector>

#include <mpi.h>

#include "ExpectError.hpp"
#include "TempFiles.hpp"
#include "cms/core/Error.hpp"
#include "cms/mesh/ScriptMeshes.hpp"

#ifndef CMS_TEST_DATA_DIR
#define CMS_TEST_DATA_DIR "tests/data"
#endif

using cms::mesh::Mesh;
using cms::mesh::ScriptMeshes;
using cms::mesh::ScriptRequest;

namespace {

const std::string kMeshes = std::string(CMS_TEST_DATA_DIR) + "/meshes/";

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

/// Rank 0's folder, its path sent to every rank (requests must be alike).
class SharedDir {
public:
  SharedDir() {
    if (rank() == 0) dir_.emplace("cms_script_meshes");
    std::string p = dir_ ? dir_->path().string() : std::string();
    unsigned long n = p.size();
    MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG, 0, MPI_COMM_WORLD);
    p.resize(n);
    MPI_Bcast(p.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
    path_ = p;
  }
  ~SharedDir() { MPI_Barrier(MPI_COMM_WORLD); }  // every rank done with the files
  /// Rank 0 writes; every rank gets the path once it is there.
  std::string write(const std::string& name, const std::string& text) const {
    if (dir_) dir_->write(name, text);
    MPI_Barrier(MPI_COMM_WORLD);
    return path_ + "/" + name;
  }

private:
  std::optional<cms::fixtures::TempDir> dir_;
  std::string path_;
};

void expectSameMesh(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.nodeTags, b.nodeTags);
  EXPECT_EQ(a.coordinates, b.coordinates);  // the same bytes read: bit for bit
  ASSERT_EQ(a.groups.size(), b.groups.size());
  for (std::size_t g = 0; g < a.groups.size(); ++g) {
    EXPECT_EQ(a.groups[g].name, b.groups[g].name);
    EXPECT_EQ(a.groups[g].dim, b.groups[g].dim);
    ASSERT_EQ(a.groups[g].blocks.size(), b.groups[g].blocks.size());
    for (std::size_t k = 0; k < a.groups[g].blocks.size(); ++k) {
      EXPECT_EQ(a.groups[g].blocks[k].type, b.groups[g].blocks[k].type);
      EXPECT_EQ(a.groups[g].blocks[k].nodes, b.groups[g].blocks[k].nodes);
    }
  }
}

}  // namespace

TEST(ScriptMeshes, EachScriptMeshedOnceTheSameMeshOnEveryRank) {
  const std::map<std::string, double> fine{{"nx", 30}}, none;
  const std::vector<ScriptRequest> requests = {{kMeshes + "bar_hex.geo", none},
                                               {kMeshes + "bar_tet10.geo", none},
                                               {kMeshes + "bar_hex.geo", fine},
                                               {kMeshes + "bar_hex.geo", none}};  // a repeat: made once
  ScriptMeshes ahead(requests, MPI_COMM_WORLD);
  // Out of order: the third first (the two before it are sent on the way).
  const auto third = ahead.take(kMeshes + "bar_hex.geo", fine);
  const auto first = ahead.take(kMeshes + "bar_hex.geo", none);
  const auto again = ahead.take(kMeshes + "bar_hex.geo", none);
  const auto second = ahead.take(kMeshes + "bar_tet10.geo", none);
  // Collectives before any assertion that could return early on one rank.
  int made = ahead.madeHere(), total = 0;
  MPI_Allreduce(&made, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(total, 3) << "each distinct script meshed once over the ranks";
  ASSERT_TRUE(first && second && third && again);
  expectSameMesh(*first, cms::mesh::readMesh(kMeshes + "bar_hex.geo"));
  expectSameMesh(*again, *first);
  expectSameMesh(*second, cms::mesh::readMesh(kMeshes + "bar_tet10.geo"));
  expectSameMesh(*third, cms::mesh::readMesh(kMeshes + "bar_hex.geo", fine));
  EXPECT_EQ(third->nodeCount(), 31u * 9);  // the parameter reached the script
  // Not requested: left to the caller, no collective (only rank 0 asks).
  if (rank() == 0) EXPECT_FALSE(ahead.take(kMeshes + "beam_line.geo", none));
}

TEST(ScriptMeshes, AScriptsErrorIsThrownOnEveryRankAsReadMeshThrowsIt) {
  SharedDir dir;
  const std::string broken = dir.write("broken.geo", "Point(1) = {0, 0, 0};\nLine(1) = {1, ;\n");
  const std::string missing = dir.write("placeholder", "") + "-missing.geo";
  std::string expected;
  try {
    cms::mesh::readMesh(broken);
  } catch (const cms::InputError& e) {
    expected = e.what();
  }
  ASSERT_FALSE(expected.empty());
  ScriptMeshes ahead({{broken, {}}, {missing, {}}, {kMeshes + "beam_line.geo", {}}}, MPI_COMM_WORLD);
  try {
    ahead.take(broken, {});
    ADD_FAILURE() << "no cms::InputError on rank " << rank();
  } catch (const cms::InputError& e) {
    EXPECT_EQ(std::string(e.what()), expected);
  }
  cms::fixtures::expectInputErrorWith([&] { ahead.take(missing, {}); }, {missing, "does not exist"});
  // The requests after a refused one are still there.
  const auto beam = ahead.take(kMeshes + "beam_line.geo", {});
  EXPECT_TRUE(beam);
  if (beam) expectSameMesh(*beam, cms::mesh::readMesh(kMeshes + "beam_line.geo"));
}

TEST(ScriptMeshes, AScriptNotTakenIsStopped) {
  // Gmsh's parser runs this loop for minutes; a scene refused after
  // starting it (a bad key further on) must not wait for it.
  SharedDir dir;
  const std::string slow = dir.write("slow.geo", "For i In {1:2000000000}\n  x = i;\nEndFor\nPoint(1) = {0, 0, 0};\n");
  const auto t0 = std::chrono::steady_clock::now();
  {
    ScriptMeshes ahead({{slow, {}}}, MPI_COMM_WORLD);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the mesher is busy by now
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The worker looks at its flag every 50 ms; 10 s is the mesher's kill and
  // the machine's noise, where the script itself runs for minutes.
  EXPECT_LT(seconds, 10.0);
}

TEST(ScriptMeshes, TheHelpersServeTheNextScenesAfterAStop) {
  // The helper slots are kept from one ScriptMeshes to the next; the one the
  // test above stopped (killed mid-script) must start afresh.
  for (int round = 0; round < 3; ++round) {
    ScriptMeshes ahead({{kMeshes + "beam_line.geo", {}}, {kMeshes + "bar_hex.geo", {}}}, MPI_COMM_WORLD);
    const auto beam = ahead.take(kMeshes + "beam_line.geo", {});
    const auto bar = ahead.take(kMeshes + "bar_hex.geo", {});
    EXPECT_TRUE(beam && bar) << "round " << round;
    if (bar) EXPECT_EQ(bar->nodeCount(), 21u * 9) << "round " << round;
  }
}

TEST(ScriptMeshes, ReadByGmshsReaderTooWhenAsked) {
  // CMS_MSH_READER=gmsh: every .msh through Gmsh's reader module, which
  // reads a file; a rank that received the bytes writes them to one first.
  ASSERT_EQ(::setenv("CMS_MSH_READER", "gmsh", 1), 0);
  {
    ScriptMeshes ahead({{kMeshes + "bar_tet10.geo", {}}, {kMeshes + "beam_line.geo", {}}}, MPI_COMM_WORLD);
    const auto bar = ahead.take(kMeshes + "bar_tet10.geo", {});
    const auto beam = ahead.take(kMeshes + "beam_line.geo", {});
    EXPECT_TRUE(bar && beam);
    if (bar) expectSameMesh(*bar, cms::mesh::readMesh(kMeshes + "bar_tet10.geo"));
    if (beam) expectSameMesh(*beam, cms::mesh::readMesh(kMeshes + "beam_line.geo"));
  }
  ASSERT_EQ(::unsetenv("CMS_MSH_READER"), 0);
}

TEST(ScriptMeshes, AFailureOnOneRankAloneIsAFailureOnEveryRank) {
  // With Gmsh's reader the receiving ranks write the bytes to a file; the
  // last rank's temporary directory made impossible, it alone fails, and
  // every rank must throw rather than go on to a collective it left.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) GTEST_SKIP() << "needs a rank that receives the mesh";
  const char* old = std::getenv("TMPDIR");
  const std::string keep = old ? old : "";
  ASSERT_EQ(::setenv("CMS_MSH_READER", "gmsh", 1), 0);
  {
    ScriptMeshes ahead({{kMeshes + "beam_line.geo", {}}}, MPI_COMM_WORLD);  // made on rank 0
    if (rank() == size - 1) ::setenv("TMPDIR", "/nonexistent/cms-test", 1);
    bool threw = false;
    try {
      ahead.take(kMeshes + "beam_line.geo", {});
    } catch (const std::exception& e) {
      threw = true;
      if (rank() != size - 1)
        EXPECT_NE(std::string(e.what()).find("rank " + std::to_string(size - 1)), std::string::npos) << e.what();
    }
    EXPECT_TRUE(threw) << "rank " << rank();
    if (old) ::setenv("TMPDIR", keep.c_str(), 1);
    else ::unsetenv("TMPDIR");
  }
  ASSERT_EQ(::unsetenv("CMS_MSH_READER"), 0);
}

TEST(ScriptMeshes, AStartFailingOnOneRankAloneIsAFailureOnEveryRank) {
  // The last rank cannot start its worker thread: its default stack made
  // larger than any address space (pthread_setattr_default_np), so
  // std::thread throws there alone. Every rank must throw from the
  // constructor instead of going on to take(), where the others would wait
  // for a rank that left; and the meshers must serve the next scene.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) GTEST_SKIP() << "needs a second rank";
  const bool last = rank() == size - 1;
  pthread_attr_t before;
  ASSERT_EQ(pthread_getattr_default_np(&before), 0);
  std::size_t stack = 0;
  ASSERT_EQ(pthread_attr_getstacksize(&before, &stack), 0);
  std::vector<ScriptRequest> requests;  // one script a rank: the last rank owns one
  for (int r = 0; r < size; ++r) requests.push_back({kMeshes + "beam_line.geo", {{"n", 4.0 + r}}});
  std::string message;
  bool threw = false;
  {
    pthread_attr_t huge;
    ASSERT_EQ(pthread_attr_init(&huge), 0);
    if (last) {
      ASSERT_EQ(pthread_attr_setstacksize(&huge, std::size_t{1} << 50), 0);
      ASSERT_EQ(pthread_setattr_default_np(&huge), 0);
    }
    try {
      ScriptMeshes ahead(requests, MPI_COMM_WORLD);
    } catch (const std::system_error& e) {
      threw = true, message = std::string("system_error: ") + e.what();
    } catch (const std::exception& e) {
      threw = true, message = e.what();
    }
    if (last) {
      pthread_attr_t normal;
      ASSERT_EQ(pthread_attr_init(&normal), 0);
      ASSERT_EQ(pthread_attr_setstacksize(&normal, stack), 0);
      ASSERT_EQ(pthread_setattr_default_np(&normal), 0);
      pthread_attr_destroy(&normal);
    }
    pthread_attr_destroy(&huge);
  }
  pthread_attr_destroy(&before);
  EXPECT_TRUE(threw) << "rank " << rank();
  if (last) EXPECT_EQ(message.rfind("system_error: ", 0), 0u) << message;
  else EXPECT_NE(message.find("rank " + std::to_string(size - 1)), std::string::npos) << message;
  // Nothing is left behind: the next scene's scripts are made and taken.
  ScriptMeshes next(requests, MPI_COMM_WORLD);
  for (const auto& r : requests) EXPECT_TRUE(next.take(r.path, r.parameters).has_value());
}
