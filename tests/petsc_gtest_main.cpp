// GoogleTest main for tests that use PETSc objects: initialise PETSc around the tests.
#include <gtest/gtest.h>
#include <petscsys.h>

int main(int argc, char **argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  const int result = RUN_ALL_TESTS();
  if (PetscFinalize()) return 1;
  return result;
}
