#include <gtest/gtest.h>

#include "psychometric.hpp"
