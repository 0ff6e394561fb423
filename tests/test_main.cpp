// GoogleTest main for tests that run scenes: PETSc and MPI around the
// tests, and only rank 0 prints.
#include <cstdio>
#include <gtest/gtest.h>

#include "run/run.h"

int main(int argc, char* argv[])
{
  ::testing::InitGoogleTest(&argc, argv);
  nct::Runtime runtime(argv[0]);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
  if (rank != 0)
  {
    // Every rank computes the same reported values: rank 0 prints them.
    delete listeners.Release(listeners.default_result_printer());
    if (!std::freopen("/dev/null", "w", stdout))
      return 1;
  }
  int code = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &code, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return code;
}
