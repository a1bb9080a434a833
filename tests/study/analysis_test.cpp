#include <gtest/gtest.h>

#include "analysis.hpp"
