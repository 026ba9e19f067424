// The campaign unit tests need MPI (PETSc sits on it) and PETSc for the ensemble statistics.
#include <gtest/gtest.h>
#include <mpi.h>

#include "campaign/ensemble.hpp"

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rc = 0;
  {
    tumble::campaign::PetscScope petsc;
    ::testing::InitGoogleTest(&argc, argv);
    rc = RUN_ALL_TESTS();
  }
  MPI_Finalize();
  return rc;
}
