#pragma once
// Writes a file whole or not at all, through the project's one checked writer
// (io/atomic_write.hpp: every write, the fsync and the close are checked before the rename), with
// the eye tracker's error type. The text is kept in memory until commit(); destroyed without
// commit() (an error midway), nothing is written.
#include <filesystem>
#include <ostream>

#include "atomic_write.hpp"
#include "error.hpp"

namespace gt::eyetrack {

class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path target) try : mFile(std::move(target)) {
    } catch (const io::WriteError& e) {
        throw EyetrackError(e.what());
    }
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return mFile.stream(); }
    [[nodiscard]] const std::filesystem::path& target() const noexcept { return mFile.target(); }
    void commit() {
        try {
            mFile.commit();
        } catch (const io::WriteError& e) {
            throw EyetrackError(e.what());
        }
    }

private:
    io::AtomicFile mFile;
};

} // namespace gt::eyetrack
