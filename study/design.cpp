#include "design.hpp"

namespace gt::study {} // namespace gt::study
