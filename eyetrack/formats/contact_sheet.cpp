#include "formats/contact_sheet.hpp"

#include <algorithm>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "error.hpp"

namespace gt::eyetrack {

namespace {
constexpr int kTileWidth = 320; // wider frames are scaled down, smaller ones kept as they are
} // namespace

ContactSheet::ContactSheet(const std::filesystem::path& png, int every)
    : mOut(png), mEvery(std::max(1, every)) {}

void ContactSheet::add(const cv::Mat& grey, const PupilResult& pupil, std::uint64_t sequence) {
    const bool keep = mSeen++ % static_cast<std::uint64_t>(mEvery) == 0;
    if (!keep || tiles() >= kMaxTiles || grey.empty()) return;
    const double s = std::min(1.0, static_cast<double>(kTileWidth) / grey.cols);
    cv::Mat tile;
    cv::resize(grey, tile, cv::Size(), s, s, cv::INTER_AREA);
    cv::cvtColor(tile, tile, cv::COLOR_GRAY2BGR);
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
    mTiles.push_back(std::move(tile));
}

void ContactSheet::write() {
    if (mTiles.empty())
        throw EyetrackError(mOut.target().string() + ": no frames for the contact sheet");
    int tw = 0, th = 0;
    for (const cv::Mat& t : mTiles) {
        tw = std::max(tw, t.cols);
        th = std::max(th, t.rows);
    }
    const int cols = std::min(kColumns, tiles());
    const int rows = (tiles() + cols - 1) / cols;
    cv::Mat sheet(rows * th, cols * tw, CV_8UC3, cv::Scalar(32, 32, 32));
    for (int i = 0; i < tiles(); ++i) {
        const cv::Mat& t = mTiles[static_cast<std::size_t>(i)];
        t.copyTo(sheet(cv::Rect((i % cols) * tw, (i / cols) * th, t.cols, t.rows)));
    }
    std::vector<uchar> bytes;
    if (!cv::imencode(".png", sheet, bytes))
        throw EyetrackError(mOut.target().string() + ": PNG encoding failed");
    mOut.stream().write(reinterpret_cast<const char*>(bytes.data()),
                        static_cast<std::streamsize>(bytes.size()));
    mOut.commit();
}

} // namespace gt::eyetrack
