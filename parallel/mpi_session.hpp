#pragma once
// MPI and FFTW's MPI interface for the lifetime of one object (RAII): the
// constructor initialises both (MPI with MPI_THREAD_FUNNELED: OpenMP threads
// inside a rank, MPI calls from its main thread only), the destructor cleans
// them up.  One per process, made first in main().
#include <mpi.h>

namespace slipstrip {

class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

int mpi_rank(MPI_Comm comm);
int mpi_size(MPI_Comm comm);

}  // namespace slipstrip
