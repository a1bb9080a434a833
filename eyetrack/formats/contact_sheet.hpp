#pragma once
// A contact sheet: every n-th frame as a tile with the detected pupil drawn over it (ellipse,
// centre and confidence; "no pupil" in red otherwise), tiled into one PNG. The quick way to see
// what the detector does on a recording that has no ground truth (a real eye).
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "formats/atomic_file.hpp"
#include "pupil/pupil_detector.hpp"

namespace gt::eyetrack {

class ContactSheet {
public:
    static constexpr int kMaxTiles = 48;
    static constexpr int kColumns = 6;

    // Keeps every `every`-th frame (from the first), up to kMaxTiles, for `png`. The file is
    // opened here (AtomicFile: a missing folder fails now, before a long recording is read) and
    // appears whole on write(), or not at all.
    ContactSheet(const std::filesystem::path& png, int every);

    void add(const cv::Mat& grey, const PupilResult& pupil, std::uint64_t sequence);
    [[nodiscard]] int tiles() const noexcept { return static_cast<int>(mTiles.size()); }

    // Writes the sheet. Throws EyetrackError when nothing was added or it cannot be written.
    void write();

private:
    AtomicFile mOut;
    int mEvery;
    std::uint64_t mSeen = 0;
    std::vector<cv::Mat> mTiles;
};

} // namespace gt::eyetrack
