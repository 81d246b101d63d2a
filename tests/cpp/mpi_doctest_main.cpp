// doctest's main() for the MPI tests: every process runs every case (their
// collective calls must match); the program fails when a case fails on any
// process.  Processes other than rank 0 print only their failures.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "parallel/mpi_session.hpp"

int main(int argc, char** argv) {
  slipstrip::MpiSession mpi(argc, argv);
  doctest::Context context(argc, argv);
  if (slipstrip::mpi_rank(MPI_COMM_WORLD) != 0) context.setOption("minimal", true);
  int failed = context.run() != 0 ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return failed;
}
