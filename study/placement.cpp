#include "placement.hpp"

namespace gt::study {} // namespace gt::study
