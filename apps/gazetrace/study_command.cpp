#include "study_command.hpp"

#include <stdexcept>

namespace gt::app {

nlohmann::json runStudy(const StudyOptions&) {
    throw std::runtime_error("study: not built yet");
}

} // namespace gt::app
