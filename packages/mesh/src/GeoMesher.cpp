// cms-geo-mesher: runs and meshes Gmsh .geo scripts, each in a process of
// its own, for cms::mesh::readGmsh (Mesh.cpp), which reads the mesh back.
//
//   cms-geo-mesher --serve     (fd 3: a socket to the cms process)
//
// A script runs arbitrary Gmsh commands, and Gmsh 4.8's mesher can hang,
// abort (std::bad_alloc, an error thrown inside an OpenMP region) or end
// the process (a script's `Exit;`); its parser fails every later script of
// a process once one failed. So no script runs in cms itself. cms starts
// this server once (exec: nothing of the possibly MPI, multi-threaded cms
// process lives on in it); the server, single-threaded and with Gmsh never
// initialised, forks one worker per script (cheap: the ~0.3 s of loading
// libgmsh and its 90 libraries is paid once) under an address-space limit,
// kills it at the time limit, and answers with how it ended.
//
// Request: NUL-terminated fields, then an empty one: TIME_LIMIT_SECONDS
// SCRIPT OUT.msh VERDICT LOG MEMORY_BYTES [NAME VALUE]... Answer, one line:
// "T" (killed at the time limit) or "S <wait status>". The worker writes
// Gmsh's terminal output to LOG (its last "Meshing surface N" line names
// what a killed mesher was doing) and exits 0 with VERDICT = "OK" and
// OUT.msh written (binary MSH 4.1, every element), or 2 with VERDICT =
// "ERROR\n<message>", the message naming a line or entity where Gmsh or the
// script says one. Any other end (a signal, exit 0 without a verdict: the
// script's `Exit;`) is for cms to describe.
#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gmsh.h>

#include "GmshSession.hpp"
#include "MesherSocket.hpp"

namespace {

using cms::mesh::detail::GmshSession;
using cms::mesh::detail::loggedErrors;
using cms::mesh::detail::sendAll;

/// Does a Gmsh message say where ("line 12", "curve 4", "surface 1")?
bool hasPlace(const std::string& message) {
  static const std::regex place(R"(([Ll]ine \d+)|(\b([Pp]oint|[Cc]urve|[Ss]urface|[Vv]olume|[Ee]ntity) -?\d+))");
  return std::regex_search(message, place);
}

/// The first error Gmsh logged, given a place when it has none: a script's
/// own `Error("...")` is found in the script by its text; otherwise the
/// first later error that names a line or entity is added ("Line requires
/// 2 points" is followed by "'x.geo', line 10: Could not add line").
std::string placedFirstError(const std::string& script) {
  const std::vector<std::string> errors = loggedErrors();
  if (errors.empty()) return {};
  const std::string& first = errors.front();
  if (hasPlace(first)) return first;
  if (!first.empty()) {
    std::ifstream in(script, std::ios::binary);
    std::string line;
    for (long n = 1; std::getline(in, line); ++n) {
      const std::size_t e = line.find("Error");
      if (e == std::string::npos || line.find(first, e) == std::string::npos) continue;
      return "line " + std::to_string(n) + ": " + first + " (the script's own Error command)";
    }
  }
  for (std::size_t i = 1; i < errors.size(); ++i)
    if (hasPlace(errors[i])) return (first.empty() ? std::string("error") : first) + " (then " + errors[i] + ")";
  return first;
}

/// Runs and meshes the script as readGmsh always did in-process; an empty
/// string when the mesh is made, else the input error's text.
std::string meshScript(const std::string& script, const std::string& out,
                       const std::vector<std::pair<std::string, double>>& parameters) {
  new GmshSession(true);  // never finalised: the worker ends right after
  try {
    for (const auto& [name, value] : parameters) gmsh::onelab::setNumber("Parameters/" + name, {value});
    // Errors logged, not thrown (Gmsh 4.8 throws them from inside OpenMP
    // regions of its mesher: std::terminate), and no "Continue?" prompt;
    // the parser then goes on past its first error, and a later message
    // can give the place the first one lacks ("Line requires 2 points",
    // then "line 10: Could not add line"). Any error is the input error.
    gmsh::option::setNumber("General.AbortOnError", 0);
    gmsh::option::setNumber("General.ExpertMode", 1);
    gmsh::open(script);
    if (const std::string error = placedFirstError(script); !error.empty()) return error;
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elementTags, nodeTags;
    gmsh::model::mesh::getElements(types, elementTags, nodeTags);
    if (types.empty()) {  // the script did not mesh itself
      gmsh::vectorpair entities;
      gmsh::model::getEntities(entities);
      int dim = -1;
      for (const auto& e : entities) dim = std::max(dim, e.first);
      // A point at an infinite coordinate (1e309 in the script) aborts
      // Gmsh 4.8's mesher (SIGABRT): named first.
      for (const auto& [d, tag] : entities) {
        if (d != 0) continue;
        std::vector<double> x;
        gmsh::model::getValue(0, tag, {}, x);
        for (double v : x)
          if (!std::isfinite(v)) {
            std::ostringstream os;
            os << "point " << tag << " has a non-finite coordinate (" << v << ")";
            return os.str();
          }
      }
      if (dim >= 0) {
        gmsh::option::setNumber("General.AbortOnError", 0);  // the script may have set it
        gmsh::model::mesh::generate(dim);
        const std::string error = placedFirstError(script);
        if (!error.empty()) return "meshing failed: " + error;
      }
    }
    // Binary (fast, exact), every element (so that the nodes read back are
    // the nodes Gmsh made, as when the script was read in-process), whatever
    // the script set.
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::option::setNumber("Mesh.Binary", 1);
    gmsh::option::setNumber("Mesh.SaveAll", 1);
    gmsh::option::setNumber("Mesh.SaveParametric", 0);
    gmsh::write(out);
    // Gmsh's writer does not report a failed write: a full disk or a
    // file-size limit left a cut .msh, which the reader then blamed on the
    // script (found by a review). A write that failed for want of room
    // fails again on one more byte: appended, then cut off again.
    {
      const int fd = ::open(out.c_str(), O_WRONLY | O_APPEND);
      const bool room = fd >= 0 && ::write(fd, "\n", 1) == 1;
      const int why = room ? 0 : errno;  // before close() can change it
      if (fd >= 0) {
        struct stat st {};
        if (room && ::fstat(fd, &st) == 0) (void)!::ftruncate(fd, st.st_size - 1);
        ::close(fd);
      }
      if (!room)
        return "Gmsh could not write the mesh it made to " + out + " (" + std::strerror(why) +
               ": disk full, or a file-size limit?)";
    }
    return {};
  } catch (const std::string& message) {  // how Gmsh 4.8 raises its errors
    const std::string first = placedFirstError(script);
    return first.empty() ? (message.empty() ? std::string("Gmsh failed to read the script") : message) : first;
  } catch (const std::bad_alloc&) {
    return "Gmsh ran out of memory (the limit is set by CMS_GEO_MEMORY_LIMIT)";
  } catch (const std::exception& e) {
    const std::string first = placedFirstError(script);
    return first.empty() ? std::string("Gmsh failed: ") + e.what() : first;
  } catch (...) {
    const std::string first = placedFirstError(script);
    return first.empty() ? std::string("Gmsh failed to read the script") : first;
  }
}

}  // namespace

namespace {

/// One request's fields (empty when the cms process closed the socket).
std::vector<std::string> readRequest(int fd, std::string& buffer) {
  for (;;) {
    // A request is complete at an empty field: "...\0\0" (or "\0" alone).
    std::size_t end = std::string::npos;
    if (!buffer.empty() && buffer[0] == '\0') end = 0;
    else if (const std::size_t at = buffer.find(std::string("\0\0", 2)); at != std::string::npos) end = at + 1;
    if (end != std::string::npos) {
      std::vector<std::string> fields;
      for (std::size_t b = 0; b < end;) {
        const std::size_t e = buffer.find('\0', b);
        fields.push_back(buffer.substr(b, e - b));
        b = e + 1;
      }
      buffer.erase(0, end + 1);
      return fields;
    }
    char chunk[4096];
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return {};
    buffer.append(chunk, static_cast<std::size_t>(n));
  }
}

/// The worker: one script, in a fresh fork of the server.
[[noreturn]] void work(const std::vector<std::string>& f) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  const std::string &script = f[1], &out = f[2], &verdict = f[3], &log = f[4];
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (fd >= 0) {
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::close(fd);
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // a killed mesher's log up to its last line
  const unsigned long long memory = std::strtoull(f[5].c_str(), nullptr, 10);
  if (memory > 0) {
    rlimit limit{};
    getrlimit(RLIMIT_AS, &limit);
    if (limit.rlim_max == RLIM_INFINITY || memory < limit.rlim_max) limit.rlim_max = memory;
    limit.rlim_cur = std::min<rlim_t>(memory, limit.rlim_max);
    setrlimit(RLIMIT_AS, &limit);
  }
  std::vector<std::pair<std::string, double>> parameters;
  for (std::size_t i = 6; i + 1 < f.size(); i += 2) parameters.emplace_back(f[i], std::strtod(f[i + 1].c_str(), nullptr));
  const std::string error = meshScript(script, out, parameters);
  {
    std::ofstream v(verdict, std::ios::binary | std::ios::trunc);
    v << (error.empty() ? "OK" : "ERROR\n" + error);
  }
  std::fflush(stdout);
  std::_Exit(error.empty() ? 0 : 2);  // no Gmsh finalize, no static destructors: nothing left to keep
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) != "--serve") {
    std::fprintf(stderr, "usage: cms-geo-mesher --serve   (started by cms, fd 3 a socket; see GeoMesher.cpp)\n");
    return 64;
  }
  prctl(PR_SET_PDEATHSIG, SIGKILL);  // die with cms
  const int fd = 3;
  std::string buffer;
  for (;;) {
    const std::vector<std::string> f = readRequest(fd, buffer);
    if (f.empty()) return 0;  // cms closed the socket
    if (f.size() < 6 || (f.size() - 6) % 2 != 0) {
      if (!sendAll(fd, "S -1\n")) return 0;
      continue;
    }
    const double seconds = std::strtod(f[0].c_str(), nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::close(fd);
      work(f);
    }
    int status = 0;
    bool timedOut = false;
    if (pid < 0) {
      status = -1;
    } else {
      // Poll (1 ms growing to 20 ms) until it ends or the time is up.
      const auto start = std::chrono::steady_clock::now();
      for (auto pause = std::chrono::microseconds(1000);;) {
        const pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid || (r < 0 && errno != EINTR)) break;
        if (std::chrono::steady_clock::now() - start > std::chrono::duration<double>(seconds)) {
          ::kill(pid, SIGKILL);
          while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
          }
          timedOut = true;
          break;
        }
        std::this_thread::sleep_for(pause);
        pause = std::min(pause * 2, std::chrono::microseconds(20000));
      }
    }
    if (!sendAll(fd, timedOut ? std::string("T\n") : "S " + std::to_string(status) + "\n")) return 0;
  }
}
