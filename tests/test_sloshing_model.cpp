#include <gtest/gtest.h>

#include "slosh/core/sloshing_model.hpp"

TEST(SloshingModel, Placeholder) { EXPECT_TRUE(true); }
