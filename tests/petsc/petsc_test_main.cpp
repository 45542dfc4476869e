// GoogleTest's main inside one PETSc session (MPI initialized once for all tests); only rank 0
// prints GoogleTest's output, every rank's failures make the exit status nonzero.
#include <gtest/gtest.h>
#include <mpi.h>

#include "petsc/petsc_linear_solver.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  tailor::PetscSession session(&argc, &argv);
  if (tailor::PetscSession::rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS() != 0 ? 1 : 0, any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return any;
}
