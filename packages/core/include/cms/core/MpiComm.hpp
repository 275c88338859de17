// The MPI communicator under a Teuchos one, for the calls Teuchos does not
// wrap (MPI_Gatherv of doubles, MPI_Comm_split_type, MUMPS's and ARPACK's
// Fortran communicators).
#pragma once

#include <mpi.h>

namespace Teuchos {
template <class Ordinal>
class Comm;
}

namespace cms {

/// `comm`'s MPI communicator; MPI_COMM_SELF for a serial Teuchos
/// communicator (one rank, no MPI underneath).
MPI_Comm rawMpiComm(const Teuchos::Comm<int>& comm);

}  // namespace cms
