#include "formats/contact_sheet.hpp"

#include <algorithm>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "error.hpp"

namespace gt::eyetrack {

namespace {
constexpr int kTileWidth = 320; // wider frames are scaled down, smaller ones kept as they are
// The pool holds up to four candidates per tile: after thinning at least two, so the candidate
// nearest each evenly spaced frame lies within a quarter of the tiles' spacing of it.
constexpr std::size_t kPoolTiles = 4 * ContactSheet::kMaxTiles;

cv::Mat drawTile(const cv::Mat& grey, double s, const PupilResult& pupil, std::uint64_t sequence) {
    cv::Mat tile;
    cv::cvtColor(grey, tile, cv::COLOR_GRAY2BGR);
    const cv::Scalar green(60, 220, 60), red(40, 40, 230), white(255, 255, 255);
    std::string label = "#" + std::to_string(sequence);
    if (pupil.found) {
        cv::RotatedRect e = pupil.ellipse;
        e.center *= static_cast<float>(s);
        e.size.width *= static_cast<float>(s);
        e.size.height *= static_cast<float>(s);
        cv::ellipse(tile, e, green, 1, cv::LINE_AA);
        cv::drawMarker(tile, e.center, green, cv::MARKER_CROSS, 7, 1);
        label += cv::format("  conf %.2f", pupil.confidence);
    } else {
        label += "  no pupil";
    }
    int baseline = 0;
    const cv::Size text = cv::getTextSize(label, cv::FONT_HERSHEY_PLAIN, 0.9, 1, &baseline);
    cv::rectangle(tile, cv::Rect(0, 0, text.width + 8, text.height + baseline + 6),
                  cv::Scalar(0, 0, 0), cv::FILLED); // legible on a bright eyelid too
    cv::putText(tile, label, {4, 4 + text.height}, cv::FONT_HERSHEY_PLAIN, 0.9,
                pupil.found ? white : red, 1, cv::LINE_AA);
    return tile;
}
} // namespace

std::vector<std::uint64_t> spreadFrames(std::uint64_t frames, int tiles) {
    std::vector<std::uint64_t> out;
    if (frames == 0 || tiles <= 0) return out;
    const auto n = static_cast<std::uint64_t>(tiles);
    if (frames <= n || n == 1) {
        for (std::uint64_t i = 0; i < std::min(frames, n); ++i)
            out.push_back(i);
        return out;
    }
    for (std::uint64_t i = 0; i < n; ++i) // rounded to the nearest frame
        out.push_back((i * (frames - 1) + (n - 1) / 2) / (n - 1));
    return out;
}

ContactSheet::ContactSheet(const std::filesystem::path& png, int every)
    : mOut(png), mEvery(std::max(1, every)), mStride(static_cast<std::uint64_t>(mEvery)) {}

void ContactSheet::add(const cv::Mat& grey, const PupilResult& pupil, std::uint64_t sequence) {
    const std::uint64_t index = mSeen++;
    if (grey.empty()) return;
    Tile t{index, sequence, {}, std::min(1.0, static_cast<double>(kTileWidth) / grey.cols), pupil};
    cv::resize(grey, t.grey, cv::Size(), t.scale, t.scale, cv::INTER_AREA);
    if (index % mStride != 0) {
        mLast = std::move(t);
        return;
    }
    mLast.reset();
    mPool.push_back(std::move(t));
    if (mPool.size() > kPoolTiles) {
        mStride *= 2;
        std::erase_if(mPool, [this](const Tile& p) { return p.index % mStride != 0; });
    }
}

std::vector<const ContactSheet::Tile*> ContactSheet::chosen() const {
    std::vector<const Tile*> candidates;
    for (const Tile& t : mPool)
        candidates.push_back(&t);
    const std::uint64_t everyN =
        (mSeen + static_cast<std::uint64_t>(mEvery) - 1) / static_cast<std::uint64_t>(mEvery);
    if (everyN <= static_cast<std::uint64_t>(kMaxTiles)) return candidates; // every n-th frame
    if (mLast) candidates.push_back(&*mLast);
    // The candidate nearest each evenly spaced frame, each after the one chosen before it.
    std::vector<const Tile*> out;
    std::size_t next = 0;
    for (const std::uint64_t f : spreadFrames(mSeen, kMaxTiles)) {
        std::size_t best = next;
        auto distance = [f](const Tile* t) { return t->index > f ? t->index - f : f - t->index; };
        for (std::size_t c = next; c < candidates.size(); ++c) {
            if (distance(candidates[c]) < distance(candidates[best])) best = c;
            if (candidates[c]->index > f) break;
        }
        if (best >= candidates.size()) break;
        out.push_back(candidates[best]);
        next = best + 1;
    }
    return out;
}

std::vector<std::uint64_t> ContactSheet::tileSequences() const {
    std::vector<std::uint64_t> out;
    for (const Tile* t : chosen())
        out.push_back(t->sequence);
    return out;
}

void ContactSheet::write() {
    const std::vector<const Tile*> shown = chosen();
    if (shown.empty())
        throw EyetrackError(mOut.target().string() + ": no frames for the contact sheet");
    int tw = 0, th = 0;
    for (const Tile* t : shown) {
        tw = std::max(tw, t->grey.cols);
        th = std::max(th, t->grey.rows);
    }
    const int count = static_cast<int>(shown.size());
    const int cols = std::min(kColumns, count);
    const int rows = (count + cols - 1) / cols;
    cv::Mat sheet(rows * th, cols * tw, CV_8UC3, cv::Scalar(32, 32, 32));
    for (int i = 0; i < count; ++i) {
        const Tile& t = *shown[static_cast<std::size_t>(i)];
        drawTile(t.grey, t.scale, t.pupil, t.sequence)
            .copyTo(sheet(cv::Rect((i % cols) * tw, (i / cols) * th, t.grey.cols, t.grey.rows)));
    }
    std::vector<uchar> bytes;
    if (!cv::imencode(".png", sheet, bytes))
        throw EyetrackError(mOut.target().string() + ": PNG encoding failed");
    mOut.stream().write(reinterpret_cast<const char*>(bytes.data()),
                        static_cast<std::streamsize>(bytes.size()));
    mOut.commit();
}

} // namespace gt::eyetrack
