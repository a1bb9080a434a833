#pragma once
// The engine's readers take their bytes through io::readInputFile (regular files of bounded
// size only) and report a refusal as their own LoadError, naming the file.
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "input_file.hpp"

namespace gt {

[[nodiscard]] inline std::string readInput(const std::filesystem::path& file,
                                           std::uint64_t maxBytes) {
    try {
        return io::readInputFile(file, maxBytes);
    } catch (const io::InputError& e) {
        throw LoadError(e.what());
    }
}

} // namespace gt
