#pragma once
// Reading a JSON file the tracker was given (a calibration, camera intrinsics): one place for the
// checks and the one-line errors that name the file.
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "error.hpp"

namespace gt::eyetrack {

// `kind` names what the file should be ("calibration"). Throws FormatError "KIND FILE: why" for a
// folder, a file that cannot be opened or text that is not JSON.
[[nodiscard]] inline nlohmann::json readJsonFile(const std::filesystem::path& file,
                                                 const std::string& kind) {
    const std::string what = kind + " " + file.string();
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) {
        throw FormatError(what + ": is a folder, not a " + kind + " file");
    }
    std::ifstream in(file);
    if (!in) {
        throw FormatError(what + ": cannot be opened");
    }
    try {
        nlohmann::json j;
        in >> j;
        return j;
    } catch (const nlohmann::json::exception&) {
        throw FormatError(what + ": not valid JSON");
    }
}

} // namespace gt::eyetrack
