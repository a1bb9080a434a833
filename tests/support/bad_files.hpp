#pragma once
// Writes a malformed file and checks that loading it fails with a gt::LoadError that names the
// file and says what is wrong.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace gt::test {

template <typename Load>
void expectLoadError(const std::filesystem::path& file, const std::string& body,
                     const std::string& mention, Load&& load) {
    {
        std::ofstream out(file);
        out << body;
    }
    try {
        load(file);
        ADD_FAILURE() << "accepted: " << body;
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(file.filename().string()), std::string::npos)
            << e.what();
    }
}

} // namespace gt::test
