#include "observer.hpp"

namespace gt::study {} // namespace gt::study
