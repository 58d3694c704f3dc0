// The tests run the library as the programs do, with one linear algebra thread: ctest runs two
// test processes at once on the 2-core CI machine, and OpenBLAS's threads, which wait for work by
// spinning, then stall each other (a design from every stretch took 3-4 times as long with them;
// numerics/linear_algebra_threads.h).
#include <gtest/gtest.h>

#include "numerics/linear_algebra_threads.h"

int main(int argc, char** argv) {
  flatmorph::set_linear_algebra_threads(1);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
