#include <gtest/gtest.h>

#include "journal.hpp"
