#pragma once
// The meshes of a scene's .geo scripts made ahead, all at once
// (doc/architecture.md, "mesh"; doc/benchmarks.md, "Scripts meshed once, side
// by side"): the scene reader starts them before it reads the substructures,
// which then take their meshes here instead of meshing one after the other.

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <mpi.h>

#include "cms/mesh/Mesh.hpp"

namespace cms::mesh {

/// A mesh to make: the arguments of readMesh for a .geo script.
struct ScriptRequest {
  std::string path;
  std::map<std::string, double> parameters;
};

/// Every rank of `comm` holds the same requests. Request i (duplicates
/// dropped) is made on rank i mod size only; a rank's requests run side by
/// side, one cms-geo-mesher each, on as many threads as its share of the
/// node's cores (coresPerRank). Each made .msh is sent to every rank,
/// which reads it as readMesh reads that script's mesh: the same mesh, or
/// the same cms::InputError naming the script, thrown on every rank.
///
/// A plain mesh file (.msh, .inp) is left to readMesh: reading it costs less
/// than sending it.
class ScriptMeshes {
public:
  /// Starts the meshing and returns. `comm`: MPI_COMM_NULL for this process
  /// alone (no MPI calls at all). Collective otherwise: a rank that cannot
  /// start (memory, a thread refused) throws its error, and the others a
  /// std::runtime_error naming it.
  ScriptMeshes(std::vector<ScriptRequest> requests, MPI_Comm comm);
  /// Stops the meshing not yet taken: its meshers are killed, its threads
  /// joined (a scene refused partway does not wait for them).
  ~ScriptMeshes();
  ScriptMeshes(const ScriptMeshes&) = delete;
  ScriptMeshes& operator=(const ScriptMeshes&) = delete;

  /// The mesh readMesh(path, parameters) would read, when it was requested;
  /// std::nullopt when not (the caller reads it itself). Collective over
  /// `comm` whenever the request is one of these: every rank takes the same
  /// requests; those before it not yet sent are sent on the way, in order.
  std::optional<Mesh> take(const std::string& path, const std::map<std::string, double>& parameters);

  /// How many scripts this rank meshed (a test's count: the ranks' sum is
  /// the number of distinct requests).
  int madeHere() const;

private:
  struct Job;
  void deliver(std::size_t upTo);
  void work(std::size_t slot);
  void stop();  ///< cancel, join the workers, release their meshers

  std::vector<std::unique_ptr<Job>> jobs_;
  std::vector<std::size_t> mine_;  ///< this rank's jobs, in order
  std::atomic<std::size_t> nextMine_{0};
  std::atomic<bool> cancel_{false};
  std::vector<std::size_t> slots_;  ///< each worker's cms-geo-mesher
  std::vector<std::thread> workers_;
  std::size_t delivered_ = 0;
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

}  // namespace cms::mesh
