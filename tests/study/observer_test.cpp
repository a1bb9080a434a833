#include <gtest/gtest.h>

#include "observer.hpp"
