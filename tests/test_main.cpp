// GoogleTest main for tests that run scenes: PETSc and MPI around the
// tests, and only rank 0 prints.
#include <dolfinx/common/log.h>
#include <gtest/gtest.h>
#include <petscsys.h>

int main(int argc, char* argv[])
{
  ::testing::InitGoogleTest(&argc, argv);
  int one = 1;
  char* argv0[] = {argv[0], nullptr};
  char** pargv = argv0;
  PetscInitialize(&one, &pargv, nullptr, nullptr);
  dolfinx::init_logging(one, pargv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0)
    delete ::testing::UnitTest::GetInstance()->listeners().Release(
        ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  int code = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &code, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  PetscFinalize();
  return code;
}
