#include <gtest/gtest.h>
#include "layers/formats.h"
TEST(Layers, Placeholder) { EXPECT_TRUE(wrsfov::layers::isSupported(wrsfov::layers::Usage::Color, wrsfov::layers::Format::RGBA8)); }
