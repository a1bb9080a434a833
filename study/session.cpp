#include "session.hpp"

namespace gt::study {} // namespace gt::study
