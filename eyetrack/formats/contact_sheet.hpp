#pragma once
// A contact sheet: every n-th frame as a tile with the detected pupil drawn over it (ellipse,
// centre and confidence; "no pupil" in red otherwise), tiled into one PNG. The quick way to see
// what the detector does on a recording that has no ground truth (a real eye). A clip with more
// n-th frames than tiles is shown whole: the tiles spread evenly from its first frame to its last.
#include <cstdint>
#include <filesystem>
#include <optional>
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

    // Keeps every `every`-th frame (from the first) for `png`: all of them when they are at most
    // kMaxTiles, else kMaxTiles spread evenly over the whole clip, first and last frame included.
    // The file is opened here (AtomicFile: a missing folder fails now, before a long recording
    // is read) and appears whole on write(), or not at all.
    ContactSheet(const std::filesystem::path& png, int every);

    void add(const cv::Mat& grey, const PupilResult& pupil, std::uint64_t sequence);
    // The tiles the sheet shows with the frames added so far, and the sequence numbers (as
    // given to add) of their frames, in order.
    [[nodiscard]] int tiles() const { return static_cast<int>(chosen().size()); }
    [[nodiscard]] std::vector<std::uint64_t> tileSequences() const;

    // Writes the sheet. Throws EyetrackError when nothing was added or it cannot be written.
    void write();

private:
    struct Tile {
        std::uint64_t index = 0;    // the frame's position among those added, from 0
        std::uint64_t sequence = 0; // as given to add
        cv::Mat grey;               // scaled to the tile's width; the drawing is added on write
        double scale = 1.0;
        PupilResult pupil;
    };
    // The pool's tiles (and the last frame's) the sheet shows.
    [[nodiscard]] std::vector<const Tile*> chosen() const;

    AtomicFile mOut;
    int mEvery;
    std::uint64_t mSeen = 0;
    // Every mStride-th frame so far (a multiple of mEvery): thinned by half whenever it holds
    // more than kPoolTiles, so a clip of any length costs a bounded memory.
    std::uint64_t mStride;
    std::vector<Tile> mPool;
    std::optional<Tile> mLast; // the newest frame: the sheet's last tile when the clip is thinned
};

// `tiles` frame positions of a clip of `frames` frames, evenly spaced, the first (0) and the
// last (frames - 1) included; all of them when the clip is shorter.
[[nodiscard]] std::vector<std::uint64_t> spreadFrames(std::uint64_t frames, int tiles);

} // namespace gt::eyetrack
