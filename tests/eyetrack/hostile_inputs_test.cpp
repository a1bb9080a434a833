// The eye tracker's file inputs against hostile files: FIFOs and devices where a file is
// expected, a playlist dressed as a video, cut videos and images, damaged JSON and CSV. Each is
// refused with one error naming the file (and the field or line), never a hang, a crash, a raw
// library message or a silently short run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "capture/file_sources.hpp"
#include "capture/frame_source.hpp"
#include "error.hpp"
#include "formats/csv_tables.hpp"
#include "formats/image_file.hpp"
#include "gaze/calibration.hpp"
#include "gaze/calibration_set.hpp"
#include "gaze/recording_calibration.hpp"
#include "model/camera_intrinsics.hpp"
#include "sim/synthetic_eye.hpp"

namespace gt::eyetrack {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() /
                       ("gazetrace_hostile_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

// The message of the error `f` throws (of type E), or a test failure.
template <typename E, typename F> std::string errorOf(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "no error";
    return {};
}

#define EXPECT_MENTIONS(text, what) EXPECT_NE((text).find(what), std::string::npos) << (text)

// A calibration with all its fields, as calibrate writes it.
nlohmann::json goodCalibration() {
    return {{"format", "gazetrace-calibration"},
            {"version", 2},
            {"model", "poly4"},
            {"display",
             {{"width_px", 1920}, {"height_px", 1080}, {"width_cm", 53.0}, {"distance_cm", 60.0}}},
            {"pupil_mean", {160.0, 120.0}},
            {"pupil_scale", {20.0, 15.0}},
            {"coefficients_x", {0.0, 10.0, 0.0, 0.0}},
            {"coefficients_y", {0.0, 0.0, -8.0, 0.0}}};
}

TEST(HostileJson, TrailingGarbageAndFifoAreRefused) {
    const fs::path dir = freshDir("json");
    write(dir / "good.json", goodCalibration().dump() + "\n  \n");
    EXPECT_NO_THROW((void)Calibration::load(dir / "good.json"));
    // A second value or stray text after the document: the file is damaged.
    write(dir / "trailing.json", goodCalibration().dump() + " garbage");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)Calibration::load(dir / "trailing.json"); }),
                    "trailing.json: not valid JSON");
    write(dir / "two.json", goodCalibration().dump() + goodCalibration().dump());
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CalibrationSet::load(dir / "two.json"); }),
                    "two.json: not valid JSON");
    // A FIFO with no writer blocked the reader forever.
    ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CalibrationSet::load(dir / "fifo.json"); }),
                    "a FIFO");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CameraIntrinsics::load(dir / "fifo.json"); }),
                    "a FIFO");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)Calibration::load("/dev/zero"); }),
                    "/dev/zero: a character device");
    fs::remove_all(dir);
}

TEST(HostileJson, EveryFieldIsTypedAndNamed) {
    const auto reject = [](const nlohmann::json& j, const std::string& field) {
        const std::string e =
            errorOf<FormatError>([&] { (void)CalibrationSet::fromJson(j, "c.json"); });
        EXPECT_MENTIONS(e, "calibration c.json: \"" + field + "\"");
        EXPECT_EQ(e.find("json.exception"), std::string::npos) << e; // nlohmann's own words
    };
    nlohmann::json j = goodCalibration();
    j["display"]["width_cm"] = "53";
    reject(j, "display.width_cm");
    j = goodCalibration();
    j["pupil_mean"] = {160.0, "x"};
    reject(j, "pupil_mean");
    j = goodCalibration();
    j["model"] = 4;
    reject(j, "model");
    j = goodCalibration();
    j.erase("pupil_scale");
    reject(j, "pupil_scale");
    j = goodCalibration();
    j["display"]["height_px"] = 2.5;
    reject(j, "display.height_px");
    j = goodCalibration();
    j["fit_error_deg"] = "small";
    reject(j, "fit_error_deg");
    // The 3D model's fields and its intrinsics, inside a version-3 file.
    nlohmann::json model3d = {
        {"intrinsics", {{"fx", 300.0}, {"fy", 300.0}, {"cx", 1.0}, {"cy", 1.0}}},
        {"rotation", {1, 0, 0, 0, 1, 0, 0, 0, 1}},
        {"eye_centre_mm", {0.0, 0.0, 35.0}},
        {"eye_radius_mm", 12.0},
        {"pupil_radius_mm", 2.0}};
    const auto v3 = [&](const nlohmann::json& m) {
        return nlohmann::json{
            {"format", "gazetrace-calibration"},
            {"version", 3},
            {"eyes", {{{"eye", "left"}, {"poly", goodCalibration()}, {"model3d", m}}}}};
    };
    EXPECT_NO_THROW((void)CalibrationSet::fromJson(v3(model3d), "c.json"));
    nlohmann::json m = model3d;
    m["eye_radius_mm"] = "12";
    reject(v3(m), "model3d.eye_radius_mm");
    m = model3d;
    m["eye_centre_mm"] = {0.0, 0.0, 1e300};
    reject(v3(m), "model3d.eye_centre_mm");
    m = model3d;
    m["intrinsics"]["fx"] = nullptr;
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CalibrationSet::fromJson(v3(m), "c.json"); }),
                    "intrinsics c.json: \"fx\" is not a number");
}

TEST(HostileCsv, TruthNumbersAreFiniteAndFramesIncrease) {
    const fs::path dir = freshDir("csv");
    const std::string header = "frame,t_ms,cx,cy,visibility,phase\n";
    write(dir / "good.csv", header + "0,0,1,2,1,calibration\n1,8.3,1,2,0,calibration\n");
    EXPECT_EQ(CsvTable::loadTruth(dir / "good.csv", {"frame"}).rows(), 2u);
    // Hand labels leave the pupil empty where none shows.
    write(dir / "labels.csv", "frame,cx,cy,visibility,note\n0,1,2,1,\n9,,,0,closed eye\n");
    EXPECT_EQ(CsvTable::loadTruth(dir / "labels.csv", {"frame"}).rows(), 2u);

    write(dir / "nan.csv", header + "0,0,1,2,1,calibration\n1,nan,1,2,0,calibration\n");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CsvTable::loadTruth(dir / "nan.csv", {}); }),
                    "nan.csv:3: t_ms 'nan' is not a number");
    write(dir / "inf.csv", header + "0,0,inf,2,1,calibration\n");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CsvTable::loadTruth(dir / "inf.csv", {}); }),
                    "inf.csv:2: cx");
    write(dir / "unsorted.csv", header + "0,0,1,2,1,a\n2,16,1,2,1,a\n1,8,1,2,1,a\n");
    EXPECT_MENTIONS(
        errorOf<FormatError>([&] { (void)CsvTable::loadTruth(dir / "unsorted.csv", {}); }),
        "unsorted.csv:4: frame 1 does not follow 2");
    write(dir / "repeat.csv", header + "0,0,1,2,1,a\n1,0,1,2,1,a\n");
    EXPECT_MENTIONS(
        errorOf<FormatError>([&] { (void)CsvTable::loadTruth(dir / "repeat.csv", {}); }),
        "repeat.csv:3: t_ms 0 does not follow 0");
    write(dir / "huge.csv", header + "1e300,0,1,2,1,a\n");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CsvTable::loadTruth(dir / "huge.csv", {}); }),
                    "huge.csv:2: frame 1e300 is not a whole frame number");
    // A target list: times strictly increasing, named by line.
    write(dir / "targets.csv", "t_ms,target_x,target_y\n0,1,1\n10,1,1\n10,5,5\n");
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)TargetSchedule::load(dir / "targets.csv"); }),
                    "targets.csv:4: t_ms");
    ASSERT_EQ(::mkfifo((dir / "fifo.csv").c_str(), 0600), 0);
    EXPECT_MENTIONS(errorOf<FormatError>([&] { (void)CsvTable::loadTruth(dir / "fifo.csv", {}); }),
                    "a FIFO");
    fs::remove_all(dir);
}

TEST(HostileVideo, PlaylistsAndUnknownContainersAreRefused) {
    EXPECT_EQ(sniffVideoContainer(std::string_view("RIFF\0\0\0\0AVI LIST", 16)),
              VideoContainer::Avi);
    EXPECT_EQ(sniffVideoContainer("\x1a\x45\xdf\xa3\x01"), VideoContainer::Matroska);
    EXPECT_EQ(sniffVideoContainer(std::string_view("\0\0\0\x20"
                                                   "ftypisom",
                                                   12)),
              VideoContainer::Mp4);
    EXPECT_EQ(sniffVideoContainer("#EXTM3U\n"), VideoContainer::Playlist);
    EXPECT_EQ(sniffVideoContainer("ffconcat version 1.0\n"), VideoContainer::Playlist);
    EXPECT_EQ(sniffVideoContainer("v=0\r\no=- 0 0 IN IP4"), VideoContainer::Playlist);
    EXPECT_EQ(sniffVideoContainer("GIF89a"), VideoContainer::Unknown);

    const fs::path dir = freshDir("video");
    // An HLS playlist named .mkv made FFmpeg read the local files it lists.
    write(dir / "playlist.mkv", "#EXTM3U\n#EXT-X-TARGETDURATION:10\n#EXTINF:10,\n/etc/hostname\n"
                                "#EXT-X-ENDLIST\n");
    EXPECT_MENTIONS(errorOf<CaptureError>([&] {
                        (void)openFrameSource(VideoFileConfig{(dir / "playlist.mkv").string()});
                    }),
                    "playlist.mkv: a playlist");
    write(dir / "text.avi", "plain text, no video");
    EXPECT_MENTIONS(errorOf<CaptureError>([&] {
                        (void)openFrameSource(VideoFileConfig{(dir / "text.avi").string()});
                    }),
                    "text.avi: not a video container");
    ASSERT_EQ(::mkfifo((dir / "fifo.mkv").c_str(), 0600), 0);
    EXPECT_MENTIONS(errorOf<CaptureError>([&] {
                        (void)openFrameSource(VideoFileConfig{(dir / "fifo.mkv").string()});
                    }),
                    "fifo.mkv: a FIFO");
    fs::remove_all(dir);
}

// A lossless clip of the synthetic eye, as eyesim writes one.
void writeClip(const fs::path& file, int frames) {
    EyeSimConfig c;
    c.frames = frames;
    c.size = {96, 72};
    const SyntheticEye eye(c);
    cv::VideoWriter w(file.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('F', 'F', 'V', '1'),
                      120.0, c.size, false);
    ASSERT_TRUE(w.isOpened());
    for (int f = 0; f < frames; ++f)
        w.write(eye.render(f));
}

// FFmpeg itself is held to plain local files once a video source has opened: a playlist that
// lists a real clip (which FFmpeg plays through its HLS demuxer otherwise) does not open even
// when handed to OpenCV directly.
TEST(HostileVideo, FfmpegIsRestrictedToTheAcceptedContainers) {
    const fs::path dir = freshDir("whitelist");
    writeClip(dir / "clip.mkv", 3);
    write(dir / "list.m3u8", "#EXTM3U\n#EXT-X-TARGETDURATION:1\n#EXTINF:1,\n" +
                                 (dir / "clip.mkv").string() + "\n#EXT-X-ENDLIST\n");
    auto source = openFrameSource(VideoFileConfig{(dir / "clip.mkv").string()});
    EXPECT_TRUE(source->next());
    const char* options = std::getenv("OPENCV_FFMPEG_CAPTURE_OPTIONS");
    ASSERT_NE(options, nullptr);
    EXPECT_MENTIONS(std::string(options), "protocol_whitelist;file|format_whitelist;");
    cv::VideoCapture direct;
    EXPECT_FALSE(direct.open((dir / "list.m3u8").string(), cv::CAP_FFMPEG));
    fs::remove_all(dir);
}

// An AVI counts its frames in its header: a file cut short by any number of frames ends in an
// error naming the count (one frame short of ten passed as a clean end).
TEST(HostileVideo, TruncatedAviEndsInAnError) {
    const fs::path dir = freshDir("cutavi");
    writeClip(dir / "clip.avi", 10);
    const auto count = [](const fs::path& p) {
        auto s = openFrameSource(VideoFileConfig{p.string()});
        int n = 0;
        while (s->next())
            ++n;
        return n;
    };
    EXPECT_EQ(count(dir / "clip.avi"), 10);
    const auto size = fs::file_size(dir / "clip.avi");
    bool sawNine = false;
    for (int percent = 30; percent < 100; percent += 5) {
        fs::copy_file(dir / "clip.avi", dir / "cut.avi", fs::copy_options::overwrite_existing);
        fs::resize_file(dir / "cut.avi", size * static_cast<unsigned>(percent) / 100);
        int read = 0;
        try {
            auto s = openFrameSource(VideoFileConfig{(dir / "cut.avi").string()});
            while (s->next())
                ++read;
        } catch (const CaptureError& e) {
            const std::string m = e.what();
            if (m.find("of the 10 its container declares") != std::string::npos) {
                EXPECT_MENTIONS(m, "cut.avi: truncated: ");
                sawNine = sawNine || m.find(": 9 frames read") != std::string::npos;
            }
            continue;
        }
        EXPECT_EQ(read, 10) << percent << "% of the file read as a clean end";
    }
    EXPECT_TRUE(sawNine) << "no cut left exactly nine frames";
    fs::remove_all(dir);
}

TEST(HostileCamera, OnlyVideoDevicesAreOpened) {
    const fs::path dir = freshDir("camera");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    for (const auto& [device, mention] :
         {std::pair<std::string, std::string>{(dir / "fifo").string(), "a FIFO"},
          {"/dev/zero", "not a camera"},
          {dir.string(), "a folder"}}) {
        V4l2Config c;
        c.device = device;
        EXPECT_MENTIONS(errorOf<CaptureError>([&] { (void)openFrameSource(c); }), mention);
    }
    fs::remove_all(dir);
}

// One PNG chunk: length, type, data and CRC-32.
std::string pngChunk(const std::string& type, const std::string& data) {
    const auto be32 = [](std::uint32_t v) {
        return std::string{static_cast<char>(v >> 24), static_cast<char>((v >> 16) & 0xff),
                           static_cast<char>((v >> 8) & 0xff), static_cast<char>(v & 0xff)};
    };
    std::uint32_t c = 0xffffffffU;
    for (const char ch : type + data) {
        c ^= static_cast<unsigned char>(ch);
        for (int k = 0; k < 8; ++k)
            c = (c & 1U) ? 0xedb88320U ^ (c >> 1) : c >> 1;
    }
    return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(c ^ 0xffffffffU);
}

// A grey 8-bit PNG of the given size around the given IDAT data.
std::string pngWith(std::uint32_t w, std::uint32_t h, const std::string& idat) {
    std::string ihdr;
    for (const std::uint32_t v : {w, h})
        for (int i = 0; i < 4; ++i)
            ihdr += static_cast<char>((v >> (24 - 8 * i)) & 0xff);
    ihdr += std::string("\x08\0\0\0\0", 5);
    return "\x89PNG\r\n\x1a\n" + pngChunk("IHDR", ihdr) + pngChunk("IDAT", idat) +
           pngChunk("IEND", "");
}

// A small PNG whose IHDR claims the given size.
std::string pngWithSize(std::uint32_t w, std::uint32_t h) {
    cv::Mat small(2, 2, CV_8U, cv::Scalar(7));
    std::vector<uchar> png;
    cv::imencode(".png", small, png);
    const std::string s(png.begin(), png.end());
    // IHDR (8 + 25 bytes) replaced; the encoder's IDAT and IEND kept.
    std::string ihdr = s.substr(16, 13);
    for (int i = 0; i < 4; ++i) {
        ihdr[static_cast<std::size_t>(i)] = static_cast<char>((w >> (24 - 8 * i)) & 0xff);
        ihdr[static_cast<std::size_t>(4 + i)] = static_cast<char>((h >> (24 - 8 * i)) & 0xff);
    }
    return s.substr(0, 8) + pngChunk("IHDR", ihdr) + s.substr(33);
}

TEST(HostileImages, SizeFromTheHeaderAndCutFilesAreOneLine) {
    const fs::path dir = freshDir("images");
    fs::create_directories(dir / "good");
    write(dir / "good" / "a.png", pngWithSize(2, 2));
    EXPECT_EQ(readImageFile(dir / "good" / "a.png").size(), cv::Size(2, 2));

    // 100000 x 100000 stopped in an OpenCV assertion that named no file.
    fs::create_directories(dir / "huge");
    write(dir / "huge" / "a.png", pngWithSize(100000, 100000).substr(0, 33)); // the header alone
    auto source = openFrameSource(ImageFolderConfig{(dir / "huge").string(), 30.0});
    EXPECT_MENTIONS(errorOf<CaptureError>([&] { (void)source->next(); }),
                    "a.png: 100000 x 100000 pixels is beyond the limit");

    // A cut PNG: one error, and no "libpng error" line of libpng's own on stderr.
    const std::string whole = pngWithSize(2, 2);
    write(dir / "cut.png", whole.substr(0, whole.size() - 20));
    testing::internal::CaptureStderr();
    const std::string cut = errorOf<CaptureError>([&] { (void)readImageFile(dir / "cut.png"); });
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_MENTIONS(cut, "cut.png: truncated PNG");

    // Image data that does not inflate, under chunks whose CRCs are right: libpng's own line
    // too, unless the data is checked first.
    write(dir / "garbage.png", pngWith(64, 48, "not zlib data at all"));
    testing::internal::CaptureStderr();
    const std::string garbage =
        errorOf<CaptureError>([&] { (void)readImageFile(dir / "garbage.png"); });
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_MENTIONS(garbage, "garbage.png: damaged PNG (its image data does not inflate)");

    // Every PNG layout OpenCV writes reads back (the checks refuse no good file).
    for (const int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_8UC4, CV_16UC3}) {
        cv::Mat m(45, 61, type);
        cv::randu(m, 0, 255);
        std::vector<uchar> png;
        cv::imencode(".png", m, png);
        write(dir / "layout.png", std::string(png.begin(), png.end()));
        const cv::Mat back = readImageFile(dir / "layout.png");
        EXPECT_EQ(cv::norm(back, m, cv::NORM_INF), 0.0) << type;
    }

    // A cut JPEG: its scan ends early, with no end marker.
    cv::Mat noise(128, 128, CV_8U);
    cv::randu(noise, 0, 255);
    std::vector<uchar> jpeg;
    cv::imencode(".jpg", noise, jpeg);
    write(dir / "cut.jpg", std::string(jpeg.begin(), jpeg.begin() + jpeg.size() * 3 / 4));
    testing::internal::CaptureStderr();
    const std::string cutJpeg =
        errorOf<CaptureError>([&] { (void)readImageFile(dir / "cut.jpg"); });
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_MENTIONS(cutJpeg, "cut.jpg: truncated JPEG");

    // Frames of another size were tracked as the same camera's (pupils in other pixels).
    fs::create_directories(dir / "mixed");
    write(dir / "mixed" / "a.png", pngWithSize(2, 2));
    write(dir / "mixed" / "b.png", pngWithSize(2, 2));
    std::vector<uchar> wider;
    cv::imencode(".png", cv::Mat(3, 4, CV_8U, cv::Scalar(7)), wider);
    write(dir / "mixed" / "c.png", std::string(wider.begin(), wider.end()));
    auto mixed = openFrameSource(ImageFolderConfig{(dir / "mixed").string(), 30.0});
    EXPECT_TRUE(mixed->next().has_value());
    EXPECT_TRUE(mixed->next().has_value());
    EXPECT_MENTIONS(errorOf<CaptureError>([&] { (void)mixed->next(); }),
                    "c.png: 4x3, but the folder's first frame");

    // A FIFO among the frames blocked the folder source forever.
    fs::create_directories(dir / "fifo");
    ASSERT_EQ(::mkfifo((dir / "fifo" / "a.png").c_str(), 0600), 0);
    auto fifo = openFrameSource(ImageFolderConfig{(dir / "fifo").string(), 30.0});
    EXPECT_MENTIONS(errorOf<CaptureError>([&] { (void)fifo->next(); }), "a.png: a FIFO");

    // Each format's header size.
    for (const char* ext : {".png", ".jpg", ".bmp", ".pgm", ".tif"}) {
        std::vector<uchar> bytes;
        cv::imencode(ext, cv::Mat(37, 53, CV_8U, cv::Scalar(5)), bytes);
        const auto size = imageHeaderSize(
            std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), ext);
        ASSERT_TRUE(size) << ext;
        EXPECT_EQ(*size, cv::Size(53, 37)) << ext;
    }
    fs::remove_all(dir);
}

} // namespace
} // namespace gt::eyetrack
