#include <gtest/gtest.h>

#include "session.hpp"
