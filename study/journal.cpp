#include "journal.hpp"

namespace gt::study {} // namespace gt::study
