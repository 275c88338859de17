#include "cms/core/MpiComm.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_DefaultMpiComm.hpp>

namespace cms {

MPI_Comm rawMpiComm(const Teuchos::Comm<int>& comm) {
  const auto* mpi = dynamic_cast<const Teuchos::MpiComm<int>*>(&comm);
  return mpi ? (*mpi->getRawMpiComm())() : MPI_COMM_SELF;
}

}  // namespace cms
