#include "capture/file_sources.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio/registry.hpp>

#include "error.hpp"
#include "formats/image_file.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::eyetrack {

// FFmpeg probes any file it is handed and follows what it names: an HLS playlist or an ffconcat
// list (whatever its extension) reads other local files into the run's output. Only plain media
// containers are let through, each by its magic number.
VideoContainer sniffVideoContainer(std::string_view head) {
    const auto at = [&](std::size_t offset, std::string_view magic) {
        return head.size() >= offset + magic.size() && head.substr(offset, magic.size()) == magic;
    };
    if (at(0, "RIFF") && at(8, "AVI ")) return VideoContainer::Avi;
    if (at(0, "\x1a\x45\xdf\xa3")) return VideoContainer::Matroska; // EBML: Matroska and WebM
    // ISO base media (MP4) and QuickTime: the first box's type.
    for (const std::string_view box : {"ftyp", "moov", "mdat", "free", "wide", "skip"})
        if (at(4, box)) return VideoContainer::Mp4;
    // Text that names other inputs: playlists (HLS, M3U, PLS), concat lists, SDP descriptions.
    for (const std::string_view text :
         {"#EXTM3U", "#EXT", "ffconcat", "[playlist]", "v=0", "<?xml"})
        if (at(0, text)) return VideoContainer::Playlist;
    return VideoContainer::Unknown;
}

UniqueFd::~UniqueFd() {
    if (mFd >= 0) ::close(mFd);
}

namespace {

// The first bytes of an opened regular file.
std::string readHead(int fd, std::size_t n) {
    std::string head(n, '\0');
    const ssize_t got = ::pread(fd, head.data(), n, 0);
    head.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
    return head;
}

// FFmpeg's open options (OpenCV 4.x reads OPENCV_FFMPEG_CAPTURE_OPTIONS, "key;value|key;value",
// at each open): the file protocol only, and only the demuxers whose magic numbers are accepted
// above, so a file that passes the sniff cannot switch FFmpeg to a playlist or a network
// protocol either. A value the user set is kept in front; ours come last and win.
void restrictFfmpeg() {
    static const std::string user = [] {
        const char* v = std::getenv("OPENCV_FFMPEG_CAPTURE_OPTIONS");
        return v != nullptr ? std::string(v) + "|" : std::string();
    }();
    const std::string options = user + "protocol_whitelist;file|format_whitelist;avi,matroska,mov";
    ::setenv("OPENCV_FFMPEG_CAPTURE_OPTIONS", options.c_str(), 1);
}

} // namespace

// A regular file of bounded size (a FIFO would block FFmpeg, a device never ends), opened once
// and kept open: FFmpeg reads this very file through /proc/self/fd, so the name cannot be swapped
// for something else between the checks and the open.
VideoFileSource::VideoFileSource(const std::filesystem::path& file)
    : mFile(file), mFd(::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)) {
    const std::string what = "video " + file.string();
    struct stat st {};
    if (mFd.get() < 0 || ::fstat(mFd.get(), &st) != 0 || !S_ISREG(st.st_mode) ||
        static_cast<std::uint64_t>(st.st_size) > io::limits::kVideoFileBytes) {
        try { // the reason, in the words every reader uses
            (void)io::checkInputFile(file, io::limits::kVideoFileBytes);
        } catch (const io::InputError& e) {
            throw CaptureError("video " + std::string(e.what()));
        }
        throw CaptureError(what + ": cannot be opened as a regular file");
    }
    if (st.st_size == 0) throw CaptureError(what + ": file is empty");
    mContainer = sniffVideoContainer(readHead(mFd.get(), 16));
    if (mContainer == VideoContainer::Playlist)
        throw CaptureError(what + ": a playlist or list of other files, not a video file (give "
                                  "the video itself: AVI, Matroska/WebM or MP4/MOV)");
    if (mContainer == VideoContainer::Unknown)
        throw CaptureError(what + ": not a video container gazetrace reads (AVI, Matroska/WebM "
                                  "or MP4/MOV, recognised by their first bytes)");
    // FFmpeg would print its own lines about damaged files; the error we raise says it in one.
    // (Read by OpenCV's FFmpeg backend when it loads; a value the user set is kept.)
    ::setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);
    restrictFfmpeg();
    // Only FFmpeg, probed first: letting OpenCV fall back to any backend made GStreamer and the
    // image-sequence reader try an unreadable file and print four lines of their own before
    // ours. OpenCV's own log is quiet while it opens.
    if (!cv::videoio_registry::hasBackend(cv::CAP_FFMPEG)) {
        throw CaptureError(what + ": this OpenCV has no FFmpeg video backend (install "
                                  "libopencv-dev from Debian, which has it)");
    }
    const std::string byFd = "/proc/self/fd/" + std::to_string(mFd.get());
    std::error_code ec;
    const std::string name =
        std::filesystem::exists(byFd, ec) ? "file:" + byFd : "file:" + file.string();
    const auto level = cv::utils::logging::getLogLevel();
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    const bool opened = mCapture.open(name, cv::CAP_FFMPEG);
    cv::utils::logging::setLogLevel(level);
    if (!opened) throw CaptureError(what + ": cannot be decoded (not a video, or truncated)");
    mFps = mCapture.get(cv::CAP_PROP_FPS);
    // A damaged header may declare any count: only a plausible one is compared with.
    const double declared = mCapture.get(cv::CAP_PROP_FRAME_COUNT);
    mExpected = declared > 0.0 && declared < 1e12 ? static_cast<std::int64_t>(declared) : 0;
}

std::optional<Frame> VideoFileSource::next() {
    cv::Mat image;
    if (!mCapture.read(image) || image.empty()) {
        if (mNext == 0)
            throw CaptureError("video " + mFile.string() +
                               ": no decodable frame (empty or truncated file)");
        // A cut file ends early without an error from the decoder: compare with the count the
        // container declares. AVI and MP4/MOV headers count their frames, so any shortfall is a
        // cut; Matroska has no count, and OpenCV estimates one from duration x rate (allow 2 %
        // there, for variable-rate recordings).
        const double declared = static_cast<double>(mExpected);
        const double allowed = mContainer == VideoContainer::Matroska ? 0.98 * declared : declared;
        if (mExpected > 0 && static_cast<double>(mNext) < allowed)
            throw CaptureError("video " + mFile.string() + ": truncated: " + std::to_string(mNext) +
                               " frames read of the " + std::to_string(mExpected) +
                               " its container declares");
        return std::nullopt;
    }
    Frame f;
    f.grey = toGrey(image);
    f.sequence = mNext;
    // The file's frame rate places each frame exactly (container timestamps are often rounded to
    // whole milliseconds); without one, the decoder's position of this frame.
    f.tMs = mFps > 0.0 ? static_cast<double>(mNext) * 1000.0 / mFps
                       : mCapture.get(cv::CAP_PROP_POS_MSEC);
    f.arrival = std::chrono::steady_clock::now();
    ++mNext;
    return f;
}

ImageFolderSource::ImageFolderSource(const std::filesystem::path& dir, double fps)
    : mDir(dir), mFps(fps) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw CaptureError("images " + dir.string() + ": no such folder");
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char ch) { return std::tolower(ch); });
        if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pgm" || ext == ".bmp" ||
            ext == ".tif" || ext == ".tiff")
            mFiles.push_back(entry.path());
    }
    if (mFiles.empty())
        throw CaptureError("images " + dir.string() + ": no image files (png, jpg, pgm, bmp, tif)");
    std::sort(mFiles.begin(), mFiles.end());
}

std::optional<Frame> ImageFolderSource::next() {
    if (mNext >= mFiles.size()) return std::nullopt;
    cv::Mat image;
    try {
        image = readImageFile(mFiles[mNext]);
    } catch (const CaptureError& e) {
        throw CaptureError(std::string(e.what()) + " (after " + std::to_string(mNext) +
                           " good frames)");
    }
    // A frame of another size (another camera's, or a resized export) was tracked as if it were
    // this camera's: its pupil positions are in other pixels, and the calibration maps them to
    // the wrong place on the screen.
    if (mNext == 0) mFrameSize = image.size();
    if (image.size() != mFrameSize) {
        throw CaptureError("images: " + mFiles[mNext].string() + ": " + std::to_string(image.cols) +
                           "x" + std::to_string(image.rows) + ", but the folder's first frame " +
                           mFiles.front().string() + " is " + std::to_string(mFrameSize.width) +
                           "x" + std::to_string(mFrameSize.height) +
                           " (one camera's frames have one size)");
    }
    Frame f;
    f.grey = toGrey(image);
    f.sequence = mNext;
    f.tMs = static_cast<double>(mNext) * 1000.0 / mFps;
    f.arrival = std::chrono::steady_clock::now();
    ++mNext;
    return f;
}

namespace {

// The synthetic eye's frame within what eyesim renders (32x24 to 4096x4096), checked before the
// eye allocates it: a source spec of any size otherwise reaches the renderer unbounded.
EyeSimConfig checkedSimConfig(EyeSimConfig c) {
    if (c.size.width < 32 || c.size.height < 24 || c.size.width > 4096 || c.size.height > 4096)
        throw CaptureError("synthetic:" + std::to_string(c.seed) + ": frame size " +
                           std::to_string(c.size.width) + "x" + std::to_string(c.size.height) +
                           " is outside 32x24..4096x4096");
    if (c.frames < 0) throw CaptureError("synthetic: a negative frame count");
    return c;
}

} // namespace

SyntheticSource::SyntheticSource(EyeSimConfig config) : mEye(checkedSimConfig(std::move(config))) {}

std::optional<Frame> SyntheticSource::next() {
    if (mNext >= mEye.config().frames) return std::nullopt;
    Frame f;
    f.grey = mEye.render(mNext);
    f.sequence = static_cast<std::uint64_t>(mNext);
    f.tMs = mEye.frameTimeMs(mNext);
    f.arrival = std::chrono::steady_clock::now();
    ++mNext;
    return f;
}

std::string SyntheticSource::describe() const {
    return "synthetic:" + std::to_string(mEye.config().seed);
}

} // namespace gt::eyetrack
