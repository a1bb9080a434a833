#pragma once
// Shared by the fuzz targets: the loaders under test read files, so each input is written to a
// file in a folder of this process's own (on /dev/shm when there is one, so a run of a million
// inputs does not wear a disk) and the loader is handed its path. Loaders read the whole file,
// so nothing of one input is seen by the next.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <unistd.h>

namespace gt::fuzz {

class InputFile {
public:
    // `name` is the file name the loader sees (its extension may matter).
    static std::filesystem::path write(std::span<const std::uint8_t> bytes,
                                       const std::string& name) {
        const std::filesystem::path file = folder() / name;
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bytes.data()),
                  static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            std::fprintf(stderr, "fuzz harness: cannot write %s\n", file.c_str());
            std::abort(); // the harness, not the target, is broken
        }
        return file;
    }

private:
    static const std::filesystem::path& folder() {
        static const std::filesystem::path dir = [] {
            std::error_code ec;
            const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                                   ? std::filesystem::path("/dev/shm")
                                                   : std::filesystem::temp_directory_path();
            std::filesystem::path d = base / ("gazetrace-fuzz-" + std::to_string(::getpid()));
            std::filesystem::create_directories(d);
            std::atexit([] {
                std::error_code ignored;
                std::filesystem::remove_all(folder(), ignored);
            });
            return d;
        }();
        return dir;
    }
};

// A finding: the target broke its contract without crashing. Prints what and aborts so that
// libFuzzer (and the replay runner) report the input.
[[noreturn]] inline void finding(const std::string& what) {
    std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
    std::abort();
}

} // namespace gt::fuzz
