// The process' BLAS is the system's: MUMPS' dgemm_ binds to the library
// Debian's libblas.so.3 alternative names (OpenBLAS here), not to one a
// dependency links in first (Debian's Ceres brings ATLAS' libf77blas,
// whose generic kernels made every factorisation 1.6 to 2.8 times slower).
#include <dlfcn.h>
#include <filesystem>

#include <gtest/gtest.h>

#include "run/run.h"

TEST(Runtime, BlasIsTheSystemAlternative)
{
  void* blas = dlopen("libblas.so.3", RTLD_NOW | RTLD_NOLOAD);
  ASSERT_NE(blas, nullptr) << "libblas.so.3 is not loaded";
  Dl_info info;
  ASSERT_NE(dladdr(dlsym(blas, "dgemm_"), &info), 0);
  EXPECT_EQ(nct::blas_library(), std::filesystem::canonical(info.dli_fname).string());
  dlclose(blas);
}
