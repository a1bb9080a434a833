#pragma once
// Writes a file whole or not at all: the text goes to a temporary beside it, renamed over the
// target on commit(); destroyed without commit (an error midway), the temporary is removed.
#include <filesystem>
#include <fstream>
#include <string>

#include "error.hpp"

namespace gt::eyetrack {

class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path target) : mTarget(std::move(target)) {
        mTemp = mTarget;
        mTemp += ".partial";
        const auto parent = mTarget.parent_path();
        std::error_code ec;
        if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
            throw EyetrackError(mTarget.string() + ": folder " + parent.string() +
                                " does not exist");
        mOut.open(mTemp, std::ios::binary | std::ios::trunc);
        if (!mOut) throw EyetrackError(mTarget.string() + ": cannot be written");
    }
    ~AtomicFile() {
        if (!mCommitted) {
            mOut.close();
            std::error_code ec;
            std::filesystem::remove(mTemp, ec);
        }
    }
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return mOut; }
    [[nodiscard]] const std::filesystem::path& target() const noexcept { return mTarget; }
    void commit() {
        mOut.flush();
        if (!mOut) throw EyetrackError(mTarget.string() + ": write failed");
        mOut.close();
        std::error_code ec;
        std::filesystem::rename(mTemp, mTarget, ec);
        if (ec)
            throw EyetrackError(mTarget.string() + ": cannot be written (" + ec.message() + ")");
        mCommitted = true;
    }

private:
    std::filesystem::path mTarget, mTemp;
    std::ofstream mOut;
    bool mCommitted = false;
};

} // namespace gt::eyetrack
