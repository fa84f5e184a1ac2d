#include "gimp/shape.hpp"
#include <gtest/gtest.h>
TEST(Shape, Placeholder) {
  EXPECT_NEAR(gimp::shape::weight(0.0, 0.25, 1.0, 1.0), 1.0 - 0.25 / 2, 1e-15);
}
