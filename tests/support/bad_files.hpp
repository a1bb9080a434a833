#pragma once
// Writes a malformed file and checks that loading it fails with a gt::LoadError that names the
// file and says what is wrong.
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/resource.h>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace gt::test {

// Runs `f`, which must throw an E, and returns its message (empty, with a failure, otherwise).
template <typename E, typename F> std::string thrownMessage(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "nothing was thrown";
    return {};
}

// How much the process's peak resident memory rose while `f` ran, in KiB: whether a loader took
// the memory a hostile file asked for, independent of the machine's speed.
template <typename F> long peakResidentGrowthKiB(F&& f) {
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    f();
    getrusage(RUSAGE_SELF, &after);
    return after.ru_maxrss - before.ru_maxrss;
}

template <typename Load>
void expectLoadError(const std::filesystem::path& file, const std::string& body,
                     const std::string& mention, Load&& load) {
    {
        std::ofstream out(file);
        out << body;
    }
    const std::string e = thrownMessage<LoadError>([&] { load(file); });
    EXPECT_NE(e.find(mention), std::string::npos) << e;
    EXPECT_NE(e.find(file.filename().string()), std::string::npos) << e;
}

} // namespace gt::test
