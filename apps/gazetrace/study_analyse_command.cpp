#include "study_analyse_command.hpp"

#include <stdexcept>

namespace gt::app {

nlohmann::json runStudyAnalyse(const StudyAnalyseOptions&) {
    throw std::runtime_error("study analyse: not built yet");
}

nlohmann::json runStudySimulate(const StudySimulateOptions&) {
    throw std::runtime_error("study simulate: not built yet");
}

} // namespace gt::app
