#include <gtest/gtest.h>

#include "design.hpp"
