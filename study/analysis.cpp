#include "analysis.hpp"

namespace gt::study {} // namespace gt::study
