// The MPI communicator under a Teuchos one, for the calls Teuchos does not
// wrap (MPI_Gatherv of doubles, MPI_Comm_split_type, MUMPS's and ARPACK's
// Fortran communicators), and the one gather of arrays to a rank that the
// gathered factorisations, MUMPS's ordering and the partitioned basis share.
#pragma once

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <mpi.h>

namespace Teuchos {
template <class Ordinal>
class Comm;
}

namespace cms {

/// `comm`'s MPI communicator; MPI_COMM_SELF for a serial Teuchos
/// communicator (one rank, no MPI underneath).
MPI_Comm rawMpiComm(const Teuchos::Comm<int>& comm);

/// Every rank's `mine` concatenated in rank order on rank `owner` of `c`
/// (empty elsewhere), by one MPI_Gatherv. Collective; throws
/// std::length_error on every rank, naming `what`, when the total exceeds
/// `limit`: MPI's int counts (a test passes a smaller one to reach the
/// refusal without 2^31 entries). For int, long long and double.
template <class T>
std::vector<T> gatherOnRank(const std::vector<T>& mine, int owner, MPI_Comm c, const char* what,
                            long long limit = INT_MAX) {
  static_assert(std::is_same<T, int>::value || std::is_same<T, long long>::value || std::is_same<T, double>::value,
                "gatherOnRank: int, long long or double");
  const MPI_Datatype type = std::is_same<T, int>::value         ? MPI_INT
                            : std::is_same<T, long long>::value ? MPI_LONG_LONG
                                                                : MPI_DOUBLE;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(c, &rank);
  MPI_Comm_size(c, &ranks);
  const bool isOwner = rank == owner;
  long long m = static_cast<long long>(mine.size()), total = 0;
  std::vector<long long> all(isOwner ? ranks : 0);
  MPI_Gather(&m, 1, MPI_LONG_LONG, all.data(), 1, MPI_LONG_LONG, owner, c);
  for (long long v : all) total += v;
  MPI_Bcast(&total, 1, MPI_LONG_LONG, owner, c);  // every rank refuses alike
  if (total > std::min<long long>(limit, INT_MAX))
    throw std::length_error(std::string(what) + ": " + std::to_string(total) + " on one rank exceed MPI's int counts");
  std::vector<int> counts(all.begin(), all.end()), offsets(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<T> out(isOwner ? static_cast<std::size_t>(total) : 0);
  MPI_Gatherv(mine.data(), static_cast<int>(m), type, out.data(), counts.data(), offsets.data(), type, owner, c);
  return out;
}

}  // namespace cms
