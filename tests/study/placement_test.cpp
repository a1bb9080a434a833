#include <gtest/gtest.h>

#include "placement.hpp"
