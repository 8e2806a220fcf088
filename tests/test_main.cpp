// GoogleTest entry point shared by every mesoflow test executable: Kokkos lives for the whole run.
#include <gtest/gtest.h>

#include "kernels/common/kokkos_compat.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  mesoflow::initialize_kokkos(-1);
  const int status = RUN_ALL_TESTS();
  Kokkos::finalize();
  return status;
}
