#include <gtest/gtest.h>
#include "shaders/wrs_common.h"
TEST(SharedMath, Placeholder) { EXPECT_NEAR(wrsfov::gpu::wrs_sample_weight(5.0f, 2.5f), 0.395f, 0.001f); }
