#include "psychometric.hpp"

namespace gt::study {} // namespace gt::study
