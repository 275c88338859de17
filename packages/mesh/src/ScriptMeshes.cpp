#include "cms/mesh/ScriptMeshes.hpp"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <new>
#include <stdexcept>

#include "cms/core/BlasThreads.hpp"
#include "cms/core/Error.hpp"
#include "ScriptRun.hpp"

namespace cms::mesh {

/// One distinct request: made by its owner's worker, then sent to every rank.
struct ScriptMeshes::Job {
  enum Kind : std::uint64_t { Bytes = 0, Input = 1, Runtime = 2, Memory = 3, Cancelled = 4 };
  ScriptRequest request;
  int owner = 0;
  std::mutex lock;
  std::condition_variable made;
  bool done = false;
  // The outcome: the .msh bytes (and whether a script made them, or the
  // file was a .msh already), or the message of what readMesh would throw.
  std::uint64_t kind = Bytes;
  bool script = true;
  std::string text;
};

ScriptMeshes::ScriptMeshes(std::vector<ScriptRequest> requests, MPI_Comm comm) : comm_(comm) {
  int nodeRanks = 1;
  if (comm_ != MPI_COMM_NULL) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    // The meshers share the node's cores with the other ranks on it.
    MPI_Comm node;
    MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &nodeRanks);
    MPI_Comm_free(&node);
  }
  // What can fail here fails on one rank alone (memory, a thread the system
  // refuses): agreed on, so that no rank goes on to take() while another
  // left, and every rank throws.
  std::exception_ptr failure;
  try {
    for (auto& r : requests) {
      const bool seen = std::any_of(jobs_.begin(), jobs_.end(), [&](const auto& j) {
        return j->request.path == r.path && j->request.parameters == r.parameters;
      });
      if (seen) continue;
      auto job = std::make_unique<Job>();
      job->request = std::move(r);
      job->owner = static_cast<int>(jobs_.size() % static_cast<std::size_t>(size_));
      if (job->owner == rank_) mine_.push_back(jobs_.size());
      jobs_.push_back(std::move(job));
    }
    const std::size_t threads =
        std::min<std::size_t>(mine_.size(), static_cast<std::size_t>(coresPerRank(nodeRanks)));
    slots_ = detail::acquireMeshers(threads);
    for (std::size_t w = 0; w < threads; ++w) workers_.emplace_back(&ScriptMeshes::work, this, slots_[w]);
  } catch (...) {
    failure = std::current_exception();
  }
  if (size_ > 1) {
    int local = failure ? rank_ : size_, first = size_;
    MPI_Allreduce(&local, &first, 1, MPI_INT, MPI_MIN, comm_);
    if (first < size_ && !failure)
      failure = std::make_exception_ptr(std::runtime_error(
          "rank " + std::to_string(first) + " could not start meshing the scene's scripts (its own message says why)"));
  }
  if (failure) {
    stop();  // no destructor runs for an object whose constructor throws
    std::rethrow_exception(failure);
  }
}

void ScriptMeshes::stop() {
  cancel_ = true;
  for (auto& t : workers_) t.join();
  workers_.clear();
  detail::releaseMeshers(slots_);  // kept for the next scene (ScriptRun.hpp)
  slots_.clear();
}

ScriptMeshes::~ScriptMeshes() { stop(); }

void ScriptMeshes::work(std::size_t slot) {
  for (std::size_t k = nextMine_++; k < mine_.size(); k = nextMine_++) {
    Job& j = *jobs_[mine_[k]];
    std::uint64_t kind = Job::Bytes;
    bool script = true;
    std::string text;
    try {
      text = detail::makeGmshBytes(j.request.path, j.request.parameters, slot, &cancel_, script);
    } catch (const detail::MeshingCancelled&) {
      kind = Job::Cancelled;
    } catch (const InputError& e) {
      kind = Job::Input, text = e.what();
    } catch (const std::bad_alloc&) {
      kind = Job::Memory;
    } catch (const std::exception& e) {
      kind = Job::Runtime, text = e.what();
    }
    {
      const std::lock_guard<std::mutex> g(j.lock);
      j.kind = kind, j.script = script, j.text = std::move(text), j.done = true;
    }
    j.made.notify_all();
  }
}

void ScriptMeshes::deliver(std::size_t upTo) {
  for (; delivered_ <= upTo; ++delivered_) {
    Job& j = *jobs_[delivered_];
    if (j.owner == rank_) {
      std::unique_lock<std::mutex> g(j.lock);
      j.made.wait(g, [&] { return j.done; });
    }
    if (size_ == 1) continue;
    // Kind, script, length; then the bytes in pieces MPI's int counts take.
    std::uint64_t head[3] = {j.kind, j.script ? 1u : 0u, j.text.size()};
    MPI_Bcast(head, 3, MPI_UINT64_T, j.owner, comm_);
    if (j.owner != rank_) {
      j.kind = head[0], j.script = head[1] != 0;
      j.text.resize(head[2]);
    }
    constexpr std::uint64_t piece = 1u << 30;
    for (std::uint64_t at = 0; at < head[2]; at += piece)
      MPI_Bcast(j.text.data() + at, static_cast<int>(std::min(piece, head[2] - at)), MPI_CHAR, j.owner, comm_);
  }
}

std::optional<Mesh> ScriptMeshes::take(const std::string& path, const std::map<std::string, double>& parameters) {
  std::size_t i = 0;
  while (i < jobs_.size() && !(jobs_[i]->request.path == path && jobs_[i]->request.parameters == parameters)) ++i;
  if (i == jobs_.size()) return std::nullopt;
  if (i >= delivered_) deliver(i);
  const Job& j = *jobs_[i];
  switch (j.kind) {
    case Job::Bytes: break;
    case Job::Input: throw InputError(j.text);
    case Job::Memory: throw std::bad_alloc();
    default: throw std::runtime_error(j.text);  // Runtime; Cancelled cannot be sent (only the destructor cancels)
  }
  // The same bytes give the same mesh or the same InputError on every rank;
  // what can fail on one rank alone (memory, the file Gmsh's reader needs)
  // is agreed on, so that no rank goes on to a collective the others left.
  std::optional<Mesh> mesh;
  std::exception_ptr failure;
  bool input = false;
  try {
    mesh = detail::meshFromGmshBytes(j.text, j.script, path);
  } catch (const InputError&) {
    failure = std::current_exception(), input = true;
  } catch (...) {
    failure = std::current_exception();
  }
  if (size_ > 1) {
    int local = failure && !input ? rank_ : size_, first = size_;
    MPI_Allreduce(&local, &first, 1, MPI_INT, MPI_MIN, comm_);
    if (first < size_ && !(failure && !input))
      throw std::runtime_error(path + ": rank " + std::to_string(first) +
                               " could not read the mesh made from this script (its own message says why)");
  }
  if (failure) std::rethrow_exception(failure);
  return mesh;
}

int ScriptMeshes::madeHere() const {
  int n = 0;
  for (std::size_t k : mine_) {
    Job& j = *jobs_[k];
    const std::lock_guard<std::mutex> g(j.lock);
    n += j.done && j.kind != Job::Cancelled;
  }
  return n;
}

}  // namespace cms::mesh
