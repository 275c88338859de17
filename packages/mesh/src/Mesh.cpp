#include "cms/mesh/Mesh.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <regex>
#include <set>
#include <sstream>
#include <string_view>
#include <thread>
#include <type_traits>
#include <utility>

#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cms/core/Error.hpp"
#include "cms/mesh/InpReader.hpp"
#include "GmshReader.hpp"
#include "MesherSocket.hpp"
#include "MshReader.hpp"
#include "MshStructureCheck.hpp"
#include "ScriptRun.hpp"

extern char** environ;

namespace cms::mesh {

const char* cellTypeName(CellType type) {
  switch (type) {
    case CellType::Point1: return "Point1";
    case CellType::Line2: return "Line2";
    case CellType::Line3: return "Line3";
    case CellType::Tri3: return "Tri3";
    case CellType::Tri6: return "Tri6";
    case CellType::Quad4: return "Quad4";
    case CellType::Tet4: return "Tet4";
    case CellType::Tet10: return "Tet10";
    case CellType::Hex8: return "Hex8";
    case CellType::Hex20: return "Hex20";
    case CellType::Wedge15: return "Wedge15";
    case CellType::Hex27: return "Hex27";
    case CellType::Hex64: return "Hex64";
    case CellType::Hex125: return "Hex125";
    case CellType::Other: return "Other";
  }
  return "Other";
}

int cellNodeCount(CellType type) {
  switch (type) {
    case CellType::Point1: return 1;
    case CellType::Line2: return 2;
    case CellType::Line3: return 3;
    case CellType::Tri3: return 3;
    case CellType::Tri6: return 6;
    case CellType::Quad4: return 4;
    case CellType::Tet4: return 4;
    case CellType::Tet10: return 10;
    case CellType::Hex8: return 8;
    case CellType::Hex20: return 20;
    case CellType::Wedge15: return 15;
    case CellType::Hex27: return 27;
    case CellType::Hex64: return 64;
    case CellType::Hex125: return 125;
    case CellType::Other: return 0;
  }
  return 0;
}

namespace {
/// The groups named `name` of dimension 0 and above 0. Two above 0 (a
/// Gmsh Physical Curve and Physical Surface of one name) are refused: which
/// one a node or element set meant cannot be told, and taking the first
/// silently clamped a root face's perimeter only (found by a review).
bool sameName(const Mesh& mesh, const std::string& a, const std::string& b) {
  if (!mesh.namesIgnoreCase) return a == b;
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
         });
}

std::pair<const PhysicalGroup*, const PhysicalGroup*> namedGroups(const Mesh& mesh, const std::string& name) {
  const PhysicalGroup *points = nullptr, *cells = nullptr;
  for (const PhysicalGroup& g : mesh.groups) {
    if (!sameName(mesh, g.name, name)) continue;
    if (g.dim == 0) {
      if (!points) points = &g;
      continue;
    }
    CMS_INPUT_CHECK(cells, mesh.source << ": the name \"" << name << "\" is given to groups of dimensions "
                                       << cells->dim << " and " << g.dim << " (tags " << cells->tag << " and "
                                       << g.tag << "): which one a set means cannot be told; rename one");
    cells = &g;
  }
  return {points, cells};
}
}  // namespace

const PhysicalGroup& Mesh::group(const std::string& name) const {
  const auto [points, cells] = namedGroups(*this, name);
  if (cells) return *cells;
  if (points) return *points;
  std::string available;
  for (const PhysicalGroup& g : groups) available += (available.empty() ? "\"" : ", \"") + g.name + "\"";
  throw InputError(source + ": no physical group named \"" + name + "\" (the mesh has " +
                   (available.empty() ? std::string("none") : available) + ")");
}

bool Mesh::hasGroup(const std::string& name) const {
  return std::any_of(groups.begin(), groups.end(),
                     [&](const PhysicalGroup& g) { return sameName(*this, g.name, name); });
}

std::vector<std::int64_t> Mesh::nodeSet(const std::string& name) const {
  const PhysicalGroup* nodeGroup = namedGroups(*this, name).first;
  const PhysicalGroup& g = nodeGroup ? *nodeGroup : group(name);
  std::vector<std::int64_t> nodes;
  for (const CellBlock& b : g.blocks) nodes.insert(nodes.end(), b.nodes.begin(), b.nodes.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

namespace {

std::string readFile(const std::string& path) {
  std::error_code ec;
  CMS_INPUT_CHECK(!std::filesystem::exists(path, ec), path << ": cannot open the file (it does not exist)");
  // A directory or device would report a meaningless size.
  CMS_INPUT_CHECK(!std::filesystem::is_regular_file(path, ec), path << ": not a regular file");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  CMS_INPUT_CHECK(!in, path << ": cannot open the file");
  const std::streamoff size = in.tellg();
  CMS_INPUT_CHECK(size < 0, path << ": cannot read the file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  CMS_INPUT_CHECK(in.gcount() != size, path << ": cannot read the file");
  return bytes;
}

bool endsWith(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i]) return false;
  return true;
}

// ---------------------------------------------------------------------------
// The mesh read through Gmsh: its SDK in a module of its own (GmshReader.cpp),
// loaded on the first .msh or .geo read.
// ---------------------------------------------------------------------------


/// Two distinct nodes closer than 1e-9 of the bounding-box diagonal are an
/// unmerged geometry (coincident faces meshed twice), which would leave the
/// parts unconnected. Cells of that size, sorted, each compared with itself
/// and its 13 lexicographically later neighbours, the neighbours found by
/// one forward sweep per offset: O(n log n). Long double keeps the extent of
/// coordinates near +-1e308 finite.
void checkDistinctNodes(const Mesh& mesh) {
  const std::size_t n = mesh.nodeCount();
  if (n < 2) return;
  long double lo[3], hi[3];
  for (int c = 0; c < 3; ++c) lo[c] = hi[c] = mesh.coordinates[c];
  for (std::size_t i = 1; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min<long double>(lo[c], mesh.coordinates[3 * i + c]);
      hi[c] = std::max<long double>(hi[c], mesh.coordinates[3 * i + c]);
    }
  long double diag2 = 0;
  for (int c = 0; c < 3; ++c) diag2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
  const long double diag = std::sqrt(diag2), tol = 1e-9L * diag;
  auto report = [&](std::size_t a, std::size_t b, long double d) {
    if (mesh.nodeTags[a] > mesh.nodeTags[b]) std::swap(a, b);
    CMS_INPUT_CHECK(true, mesh.source << ": nodes " << mesh.nodeTags[a] << " and " << mesh.nodeTags[b]
                                      << " coincide (distance " << static_cast<double>(d)
                                      << ", below 1e-9 of the mesh size " << static_cast<double>(diag)
                                      << "): an unmerged geometry?");
  };
  if (tol == 0) report(0, 1, 0);

  struct Item {
    std::int64_t key[3];
    std::size_t node;
  };
  std::vector<Item> items(n);
  for (std::size_t i = 0; i < n; ++i) {
    items[i].node = i;
    for (int c = 0; c < 3; ++c)
      items[i].key[c] = static_cast<std::int64_t>(std::floor((mesh.coordinates[3 * i + c] - lo[c]) / tol));
  }
  auto less = [](const std::int64_t* a, const std::int64_t* b) {
    return std::lexicographical_compare(a, a + 3, b, b + 3);
  };
  std::sort(items.begin(), items.end(), [&](const Item& a, const Item& b) { return less(a.key, b.key); });
  struct Cell {
    std::int64_t key[3];
    std::size_t begin, end;
  };
  std::vector<Cell> cells;
  for (std::size_t i = 0; i < n; ++i) {
    if (cells.empty() || !std::equal(items[i].key, items[i].key + 3, cells.back().key))
      cells.push_back({{items[i].key[0], items[i].key[1], items[i].key[2]}, i, i});
    cells.back().end = i + 1;
  }
  auto close = [&](std::size_t a, std::size_t b) {
    long double d2 = 0;
    for (int c = 0; c < 3; ++c) {
      const long double d = static_cast<long double>(mesh.coordinates[3 * a + c]) - mesh.coordinates[3 * b + c];
      d2 += d * d;
    }
    if (d2 <= tol * tol) report(a, b, std::sqrt(d2));
  };
  std::vector<std::array<int, 3>> offsets;
  for (int dx = 0; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (dx > 0 || dy > 0 || (dy == 0 && dz > 0)) offsets.push_back({dx, dy, dz});
  std::vector<std::size_t> cursor(offsets.size(), 0);
  for (const Cell& cell : cells) {
    for (std::size_t i = cell.begin; i < cell.end; ++i)
      for (std::size_t j = i + 1; j < cell.end; ++j) close(items[i].node, items[j].node);
    for (std::size_t o = 0; o < offsets.size(); ++o) {
      const std::int64_t target[3] = {cell.key[0] + offsets[o][0], cell.key[1] + offsets[o][1],
                                      cell.key[2] + offsets[o][2]};
      std::size_t& k = cursor[o];
      while (k < cells.size() && less(cells[k].key, target)) ++k;
      if (k == cells.size() || !std::equal(target, target + 3, cells[k].key)) continue;
      for (std::size_t i = cell.begin; i < cell.end; ++i)
        for (std::size_t j = cells[k].begin; j < cells[k].end; ++j) close(items[i].node, items[j].node);
    }
  }
}

detail::GmshReadMsh gmshReader();  // below, with the other files of libexec/cms

/// Whether MSH 4.1 files are read without Gmsh (MshReader.cpp): yes unless
/// CMS_MSH_READER=gmsh sends every file to the Gmsh reader module.
bool readWithoutGmsh() {
  const char* v = std::getenv("CMS_MSH_READER");
  if (!v || !*v) return true;
  const std::string reader(v);
  CMS_INPUT_CHECK(reader != "gmsh" && reader != "cms",
                  "environment variable CMS_MSH_READER = \"" << reader << "\" must be \"cms\" or \"gmsh\"");
  return reader == "cms";
}

/// Reads a .msh through Gmsh in this process (the file passed
/// checkMshStructure), by the Gmsh reader module loaded on first use
/// (gmshReader); every failure is an InputError naming `source`.
Mesh readMshInProcess(const std::string& path, const std::string& source) {
  Mesh mesh;
  std::string message;
  switch (gmshReader()(path.c_str(), source.c_str(), &mesh, &message, &checkDistinctNodes)) {
    case detail::kGmshReadOk: break;
    case detail::kGmshReadOutOfMemory: throw std::bad_alloc();
    default: throw InputError(message);
  }
  return mesh;
}

/// A checked .msh (its bytes already scanned into `content`, or not): read
/// without Gmsh when it is MSH 4.1, else by Gmsh's SDK in the reader module.
Mesh readScannedMsh(detail::MshContent& content, const std::string& path, const std::string& source) {
  if (content.captured) return detail::meshFromMsh41(std::move(content), source, &checkDistinctNodes);
  return readMshInProcess(path, source);
}

// ---------------------------------------------------------------------------
// .geo scripts: run and meshed by the cms-geo-mesher helper (GeoMesher.cpp)
// in a child process with a time and an address-space limit, its .msh read
// back in this process.
// ---------------------------------------------------------------------------

/// A positive number from the environment, or `fallback` when unset.
double positiveFromEnvironment(const char* name, double fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(v, &end);
  CMS_INPUT_CHECK(end == v || *end != '\0' || errno != 0 || !std::isfinite(x) || x <= 0,
                  "environment variable " << name << " = \"" << v << "\" must be a positive number");
  return x;
}

/// A file of libexec/cms (the .geo mesher, the Gmsh reader module), found
/// without any path compiled in (doc/architecture.md, "Install layout"):
/// $`variable` when set, else libexec/cms/`name` one level above the
/// directory of the running program or of the library holding this code
/// (installed: <prefix>/bin/cms and <prefix>/lib find <prefix>/libexec/cms;
/// in the build tree every program sits one level below build/, and the
/// build puts the helpers in build/libexec/cms), else beside the running
/// program. `mode` is access()'s (X_OK, R_OK). Throws cms::InputError
/// naming every place tried.
std::string libexecFile(const char* name, const char* variable, const char* what, const char* purpose, int mode) {
  if (const char* v = std::getenv(variable); v && *v) {
    CMS_INPUT_CHECK(::access(v, mode) != 0, what << ": " << variable << " = " << v << " is not "
                                                 << (mode == X_OK ? "an executable" : "a readable") << " file ("
                                                 << std::strerror(errno) << "); unset it to use the installed "
                                                 << name << " (<prefix>/libexec/cms/" << name << ")");
    return v;
  }
  // The running program and the library holding this code (the program
  // itself when libcms_mesh is linked statically).
  std::vector<std::filesystem::path> homes;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) homes.push_back(self);
  Dl_info library{};
  if (::dladdr(reinterpret_cast<void*>(&libexecFile), &library) != 0 && library.dli_fname && *library.dli_fname)
    homes.push_back(std::filesystem::absolute(library.dli_fname, ec));
  std::vector<std::filesystem::path> candidates;
  for (const auto& home : homes) {
    const auto c = (home.parent_path().parent_path() / "libexec" / "cms" / name).lexically_normal();
    if (std::find(candidates.begin(), candidates.end(), c) == candidates.end()) candidates.push_back(c);
  }
  if (!self.empty()) candidates.push_back(self.parent_path() / name);
  std::string tried;
  for (const auto& c : candidates) {
    if (::access(c.c_str(), mode) == 0) return c.string();
    tried += (tried.empty() ? "" : ", ") + c.string();
  }
  CMS_INPUT_CHECK(true, "cannot find " << what << " " << name << ", which " << purpose << " (tried: "
                                       << (tried.empty() ? "nothing" : tried) << "); set " << variable
                                       << " to its path (installed: <prefix>/libexec/cms/" << name << ")");
  return {};
}

std::string geoMesherPath() {
  return libexecFile("cms-geo-mesher", "CMS_GEO_MESHER", "the .geo mesher", "meshes .geo scripts", X_OK);
}

/// The Gmsh reader module's entry point, the module loaded on the first call
/// and kept (Gmsh's SDK is a global state that outlives a read). Not loaded
/// at all by a run without a Gmsh mesh.
detail::GmshReadMsh gmshReader() {
  static std::mutex lock;
  static detail::GmshReadMsh entry = nullptr;
  const std::lock_guard<std::mutex> guard(lock);
  if (entry) return entry;
  const std::string path =
      libexecFile(detail::kGmshReaderModule, "CMS_GMSH_READER", "the Gmsh reader module", "reads .msh files", R_OK);
  void* module = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  CMS_INPUT_CHECK(!module, "cannot load the Gmsh reader module " << path << ": " << ::dlerror());
  entry = reinterpret_cast<detail::GmshReadMsh>(::dlsym(module, detail::kGmshReadMshSymbol));
  CMS_INPUT_CHECK(!entry, "the Gmsh reader module " << path << " has no " << detail::kGmshReadMshSymbol
                                                    << " (a module of another build?)");
  return entry;
}
/// The cms-geo-mesher server of this process (GeoMesher.cpp): started by
/// the first .geo read, kept for the next ones, ended (it reads end of file)
/// when this process exits. A process forked from this one starts its own.
class GeoMesherServer {
public:
  /// Sends a request, returns the answer line ("T" or "S <status>"), or ""
  /// when the server died without answering, or "C" when `cancel` was set
  /// meanwhile (the server then killed). One request at a time: a second
  /// caller waits for the first.
  std::string ask(const std::vector<std::string>& fields, double seconds,
                  const std::atomic<bool>* cancel = nullptr) {
    const std::lock_guard<std::mutex> one(busy_);
    std::string request;
    for (const std::string& f : fields) request += f + '\0';
    request += '\0';
    for (int attempt = 0; attempt < 2; ++attempt) {
      start();
      if (sendAll(request)) break;
      stop();  // a dead server (killed?): one fresh start
      if (attempt == 1) return {};
    }
    // The server enforces the time limit; this is a backstop should it hang.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds + 30);
    std::string line;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) {
        stop();
        return "T";
      }
      if (cancel && cancel->load()) {
        stop();
        return "C";
      }
      pollfd p{fd_, POLLIN, 0};
      // A cancellable request looks at its flag every 50 ms.
      const long long wait = std::min<long long>(left.count(), cancel ? 50 : 1000000);
      const int r = ::poll(&p, 1, static_cast<int>(wait));
      if (r < 0 && errno == EINTR) continue;
      if (r == 0) continue;
      char c = 0;
      const ssize_t n = r > 0 ? ::read(fd_, &c, 1) : -1;
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        stop();
        return {};
      }
      if (c == '\n') return line;
      line += c;
    }
  }
  ~GeoMesherServer() {
    if (owner_ == ::getpid()) stop();
  }

private:
  void start() {
    if (fd_ >= 0 && owner_ == ::getpid()) return;
    if (fd_ >= 0) ::close(fd_);  // inherited from the process this one was forked from: its server
    fd_ = -1;
    pid_ = -1;
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
      throw std::runtime_error(std::string("cannot start the .geo mesher: socketpair: ") + std::strerror(errno));
    const std::string helper = geoMesherPath();
    std::string serve = "--serve";
    std::string program = helper;
    char* argv[] = {program.data(), serve.data(), nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, sv[1], 3);
    pid_t pid = 0;
    const int spawned = ::posix_spawn(&pid, helper.c_str(), &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(sv[1]);
    if (spawned != 0) {
      ::close(sv[0]);
      throw std::runtime_error("cannot start the .geo mesher " + helper + " (set CMS_GEO_MESHER to its path): " +
                               std::strerror(spawned));
    }
    fd_ = sv[0];
    pid_ = pid;
    owner_ = ::getpid();
    spawner_ = std::this_thread::get_id();
  }
  void stop() {
    if (fd_ >= 0) ::close(fd_);
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      while (::waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {
      }
    }
    fd_ = -1;
    pid_ = -1;
  }
  bool sendAll(const std::string& s) { return detail::sendAll(fd_, s); }
  friend std::vector<std::size_t> detail::acquireMeshers(std::size_t);
  friend void detail::releaseMeshers(const std::vector<std::size_t>&);
  std::mutex busy_;
  int fd_ = -1;
  pid_t pid_ = -1, owner_ = -1;
  std::thread::id spawner_;  ///< the thread whose end kills the helper (PR_SET_PDEATHSIG)
};

/// Mesher server number `slot` of this process, started on its first
/// request: readGmsh uses slot 0, each ScriptMeshes worker a slot of its own
/// (detail::newMesherSlot).
std::mutex serversLock;
std::deque<GeoMesherServer> servers;  // a deque: references stay valid as it grows

GeoMesherServer& mesherServer(std::size_t slot) {
  const std::lock_guard<std::mutex> guard(serversLock);
  while (servers.size() <= slot) servers.emplace_back();
  return servers[slot];
}

/// A private directory for the helper's files, removed with this object.
class TemporaryDirectory {
public:
  TemporaryDirectory() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/cms-geo-XXXXXX";
    if (!::mkdtemp(pattern.data()))
      throw std::runtime_error("cannot create a temporary directory " + pattern + " for meshing: " +
                               std::strerror(errno));
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  std::string file(const char* name) const { return (path_ / name).string(); }

private:
  std::filesystem::path path_;
};

/// What the mesher was doing last, from its Gmsh log: " while meshing
/// surface 3" (the last entity it started), or "".
std::string lastActivity(const std::string& log) {
  std::string bytes;
  try {
    bytes = readFile(log);
  } catch (...) {
    return {};
  }
  static const std::regex meshing(R"(Meshing (curve|surface|volume) (\d+))");
  std::string last;
  for (std::sregex_iterator it(bytes.begin(), bytes.end(), meshing), end; it != end; ++it)
    last = " while meshing " + (*it)[1].str() + " " + (*it)[2].str();
  return last;
}

/// The line of a script's first `Exit;` command (0 if none is found).
long exitCommandLine(const std::string& script) {
  std::ifstream in(script, std::ios::binary);
  static const std::regex exitCommand(R"((^|[^A-Za-z0-9_])Exit\s*;)");
  std::string line;
  for (long n = 1; std::getline(in, line); ++n) {
    const std::size_t comment = line.find("//");
    if (std::regex_search(line.substr(0, comment), exitCommand)) return n;
  }
  return 0;
}

/// The .msh a mesher server made from a script, in its private directory.
struct MadeScript {
  std::unique_ptr<TemporaryDirectory> dir;
  std::string msh;
};

/// Thrown by runScript when its request was cancelled (ScriptMeshes' end).
struct ScriptCancelled {};

/// Runs a .geo script in `server`: the .msh's file, or an InputError naming
/// the script (died, timed out, crashed, Gmsh's error, an Exit command).
/// Thread-safe with another server per thread; reads nothing through Gmsh.
MadeScript runScript(const std::string& path, const std::map<std::string, double>& parameters,
                     GeoMesherServer& server, const std::atomic<bool>* cancel = nullptr) {
  const double seconds = positiveFromEnvironment("CMS_GEO_TIME_LIMIT", 600);
  // Default: the machine's memory (no swapping storm); in MB.
  const double physicalMb =
      static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE)) / 1048576.0;
  const double memoryMb = positiveFromEnvironment("CMS_GEO_MEMORY_LIMIT", physicalMb > 0 ? physicalMb : 0x1p30);
  MadeScript made{std::make_unique<TemporaryDirectory>(), {}};
  const TemporaryDirectory& dir = *made.dir;
  const std::string out = dir.file("mesh.msh"), verdict = dir.file("verdict"), log = dir.file("gmsh.log");
  made.msh = out;
  std::ostringstream limit;
  limit << std::setprecision(17) << seconds;
  // Fields travel NUL-terminated, an empty one ending the request.
  CMS_INPUT_CHECK(path.find('\0') != std::string::npos, path << ": the file name has a NUL character");
  for (const auto& [name, value] : parameters)
    CMS_INPUT_CHECK(name.empty() || name.find('\0') != std::string::npos,
                    path << ": mesh parameter \"" << name << "\": the name is empty or has a NUL character");
  // Absolute: the helper keeps the directory this process had when it started it.
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  std::vector<std::string> fields = {limit.str(), ec ? path : absolute.string(), out, verdict, log,
                                     std::to_string(static_cast<unsigned long long>(memoryMb * 1048576.0))};
  for (const auto& [name, value] : parameters) {
    char number[40];
    std::snprintf(number, sizeof number, "%.17g", value);
    fields.push_back(name);
    fields.push_back(number);
  }
  const std::string answer = server.ask(fields, seconds, cancel);
  if (answer == "C") throw ScriptCancelled{};
  const bool timedOut = answer == "T";
  int status = 0;
  if (answer.compare(0, 2, "S ") == 0) status = std::atoi(answer.c_str() + 2);
  CMS_INPUT_CHECK(answer.empty(), path << ": the Gmsh mesher process died while meshing this script"
                                       << lastActivity(log) << " - out of memory?");

  std::string said;
  {
    std::ifstream in(verdict, std::ios::binary);
    said.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::ostringstream limits;
  limits << " (limits: " << seconds << " s, set by CMS_GEO_TIME_LIMIT; " << std::llround(memoryMb)
         << " MB, set by CMS_GEO_MEMORY_LIMIT)";
  CMS_INPUT_CHECK(timedOut, path << ": Gmsh did not finish this script within " << seconds << " s"
                                 << lastActivity(log) << limits.str());
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::strsignal(sig);
    CMS_INPUT_CHECK(true, path << ": Gmsh crashed on this script (signal " << sig << ", " << (name ? name : "?")
                               << ")" << lastActivity(log)
                               << (sig == SIGKILL ? " - out of memory?" : "")
                               << limits.str());
  }
  if (said.compare(0, 6, "ERROR\n") == 0) throw InputError(path + ": " + said.substr(6));
  if (said != "OK") {
    const long exitLine = exitCommandLine(path);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    CMS_INPUT_CHECK(exitLine > 0, path << ": line " << exitLine
                                       << ": the script's Exit command ended Gmsh before the mesh was made");
    CMS_INPUT_CHECK(true, path << ": Gmsh ended (exit status " << code << ") before the mesh was made"
                               << lastActivity(log));
  }
  return made;
}

/// The mesh of the .msh bytes Gmsh made from the script `source`, read as
/// any .msh is: scanned all the same (cheap next to meshing), then read
/// without Gmsh, or by its module from a file of those bytes.
Mesh meshFromMadeScript(const std::string& bytes, const std::string& source) {
  detail::MshContent content;
  const bool withoutGmsh = readWithoutGmsh();
  std::unique_ptr<TemporaryDirectory> dir;
  std::string path = "mesh.msh";  // names it in messages
  if (!withoutGmsh) {
    dir = std::make_unique<TemporaryDirectory>();
    path = dir->file("mesh.msh");
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    CMS_INPUT_CHECK(!out.flush(), path << ": cannot write the mesh made from " << source << " for Gmsh's reader");
  }
  try {
    detail::checkMshStructure(path, bytes, withoutGmsh ? &content : nullptr);
  } catch (const InputError& e) {
    throw InputError(source + ": the mesh Gmsh made from this script cannot be read back: " + e.what());
  }
  return readScannedMsh(content, path, source);
}

/// The bytes of the .msh a script made; an InputError naming the script if
/// they cannot be read.
std::string madeBytes(const MadeScript& made, const std::string& source) {
  try {
    return readFile(made.msh);
  } catch (const InputError& e) {
    throw InputError(source + ": the mesh Gmsh made from this script cannot be read back: " + e.what());
  }
}


}  // namespace

namespace detail {

namespace {
std::vector<std::size_t> freeSlots;  // under serversLock
}  // namespace

std::vector<std::size_t> acquireMeshers(std::size_t count) {
  std::vector<std::size_t> slots;
  slots.reserve(count);  // no push_back below can throw
  {
    const std::lock_guard<std::mutex> guard(serversLock);
    // Room for every slot to go back, reserved before any is taken: should
    // a new server's allocation throw below, the slots taken so far return
    // to the free list instead of being lost to every later scene.
    freeSlots.reserve(freeSlots.size() + count);
    while (slots.size() < count && !freeSlots.empty()) slots.push_back(freeSlots.back()), freeSlots.pop_back();
    try {
      if (servers.empty()) servers.emplace_back();  // slot 0 stays readGmsh's
      while (slots.size() < count) {
        servers.emplace_back();
        slots.push_back(servers.size() - 1);
      }
    } catch (...) {
      freeSlots.insert(freeSlots.end(), slots.begin(), slots.end());
      throw;
    }
  }
  // Started here, on the caller's thread, so that they outlive the workers;
  // a failure to start is left for the worker's request to report.
  for (std::size_t slot : slots) {
    GeoMesherServer& server = mesherServer(slot);
    const std::lock_guard<std::mutex> one(server.busy_);
    try {
      server.start();
    } catch (const std::exception&) {
    }
  }
  return slots;
}

void releaseMeshers(const std::vector<std::size_t>& slots) {
  for (std::size_t slot : slots) {
    GeoMesherServer& server = mesherServer(slot);
    {
      const std::lock_guard<std::mutex> one(server.busy_);
      // A helper a worker restarted dies with that worker: not kept.
      if (server.owner_ == ::getpid() && server.spawner_ != std::this_thread::get_id()) server.stop();
    }
    const std::lock_guard<std::mutex> guard(serversLock);
    freeSlots.push_back(slot);
  }
}

namespace {
/// Every name a script, and the files it includes, gives as
/// "Parameters/<name>" (DefineConstant[h = {0.01, Name "Parameters/h"}], or
/// GetNumber of it): the ONELAB numbers "Mesh Parameters" set.
void namedParameters(const std::filesystem::path& path, const std::string& text, std::set<std::string>& names,
                     std::set<std::filesystem::path>& seen) {
  static const std::regex parameter(R"(Parameters/([A-Za-z_][A-Za-z0-9_]*))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), parameter); it != std::sregex_iterator(); ++it)
    names.insert((*it)[1].str());
  static const std::regex include(R"re(Include\s*"([^"]+)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), include); it != std::sregex_iterator(); ++it) {
    std::error_code ec;
    const auto file = std::filesystem::weakly_canonical(path.parent_path() / (*it)[1].str(), ec);
    if (ec || !seen.insert(file).second || !std::filesystem::is_regular_file(file, ec)) continue;
    std::ifstream in(file, std::ios::binary);  // a missing include is Gmsh's to report
    const std::string inner((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    namedParameters(file, inner, names, seen);
  }
}
}  // namespace

std::string makeGmshBytes(const std::string& path, const std::map<std::string, double>& parameters, std::size_t slot,
                          const std::atomic<bool>* cancel, bool& script) {
  std::string bytes = readFile(path);
  script = bytes.compare(0, 11, "$MeshFormat") != 0;
  if (!script) return bytes;
  CMS_INPUT_CHECK(!endsWith(path, ".geo"), path << ": not a Gmsh mesh (a .msh file starts with $MeshFormat) nor a "
                                                   ".geo script");
  // A parameter the script does not name would set a ONELAB number nothing
  // reads: "h" misspelt "hh" meshed at the script's default, silently
  // (found by a review).
  if (!parameters.empty()) {
    std::set<std::string> names;
    std::set<std::filesystem::path> seen;
    namedParameters(path, bytes, names, seen);
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "\"Parameters/" : ", \"Parameters/") + n + "\"";
    for (const auto& [name, value] : parameters)
      CMS_INPUT_CHECK(!names.count(name), path << ": mesh parameter \"" << name << "\": the script names no \"Parameters/"
                                                << name << "\" (it names " << (known.empty() ? std::string("none") : known)
                                                << "), so it would be ignored");
  }
  try {
    const MadeScript made = runScript(path, parameters, mesherServer(slot), cancel);
    return madeBytes(made, path);
  } catch (const ScriptCancelled&) {
    throw MeshingCancelled();
  }
}

Mesh meshFromGmshBytes(const std::string& bytes, bool script, const std::string& path) {
  if (script) return meshFromMadeScript(bytes, path);
  detail::MshContent content;
  detail::checkMshStructure(path, bytes, readWithoutGmsh() ? &content : nullptr);
  return readScannedMsh(content, path, path);
}

}  // namespace detail

Mesh readGmsh(const std::string& path, const std::map<std::string, double>& parameters) {
  bool script = false;
  const std::string bytes = detail::makeGmshBytes(path, parameters, 0, nullptr, script);
  return detail::meshFromGmshBytes(bytes, script, path);
}

Mesh readMesh(const std::string& path, const std::map<std::string, double>& parameters) {
  if (!endsWith(path, ".inp")) return readGmsh(path, parameters);
  CMS_INPUT_CHECK(!parameters.empty(), path << ": mesh parameters apply to a .geo script only, not to an .inp deck");
  return readInp(path);
}

}  // namespace cms::mesh
