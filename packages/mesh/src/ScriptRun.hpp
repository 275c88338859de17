#pragma once
// Private to cms_mesh: readGmsh cut in two, so that ScriptMeshes can make a
// script's mesh on one rank's worker thread and read it on every rank.

#include <atomic>
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "cms/mesh/Mesh.hpp"

namespace cms::mesh::detail {

/// Thrown by makeGmshBytes when its `cancel` flag was set (its mesher killed).
struct MeshingCancelled : std::runtime_error {
  MeshingCancelled() : std::runtime_error("meshing cancelled") {}
};

/// `count` mesher server slots for worker threads (readGmsh has slot 0),
/// kept across ScriptMeshes: their helpers started on the calling thread. A
/// helper dies with the thread that started it (PR_SET_PDEATHSIG follows
/// the thread, not the process), so one a worker had to restart is stopped
/// by releaseMeshers (called on the same thread once the workers are done),
/// and nothing sends a request to a helper about to die.
std::vector<std::size_t> acquireMeshers(std::size_t count);
void releaseMeshers(const std::vector<std::size_t>& slots);

/// readGmsh's first half: the bytes of `path` when it is a .msh (`script`
/// false), else of the .msh its .geo script made in mesher server `slot`
/// (`script` true). The same cms::InputError as readGmsh, naming `path`.
/// Thread-safe with one slot per thread; nothing read through Gmsh's SDK.
std::string makeGmshBytes(const std::string& path, const std::map<std::string, double>& parameters, std::size_t slot,
                          const std::atomic<bool>* cancel, bool& script);

/// readGmsh's second half: the mesh of those bytes, as readGmsh(path)
/// returns it. Not thread-safe (Gmsh's reader module).
Mesh meshFromGmshBytes(const std::string& bytes, bool script, const std::string& path);

}  // namespace cms::mesh::detail
