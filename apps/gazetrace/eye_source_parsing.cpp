#include "eye_source_parsing.hpp"

#include <arpa/inet.h>

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "core/error.hpp"

namespace gt::app {

namespace {

std::string describeRange(double lo, double hi) {
    char text[64];
    std::snprintf(text, sizeof text, "%.15g..%.15g", lo, hi);
    return text;
}

// "key=value&key=value" into `options`; `spec` names the whole source in errors.
void splitQuery(const std::string& spec, const std::string& query,
                std::map<std::string, std::string>& options) {
    std::size_t pos = 0;
    while (pos <= query.size()) {
        const auto amp = query.find('&', pos);
        const std::string item =
            query.substr(pos, amp == std::string::npos ? std::string::npos : amp - pos);
        if (!item.empty()) {
            const auto eq = item.find('=');
            if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
                throw ArgumentError("frame source '" + spec + "': option '" + item +
                                    "' is not key=value");
            options[item.substr(0, eq)] = item.substr(eq + 1);
        }
        if (amp == std::string::npos) break;
        pos = amp + 1;
    }
}

// The ranges a source's numeric options must lie in: the eye cameras gazetrace reads and the
// clips eyesim renders (its --fps, --frames and --size take the same). Unbounded, fps=1e-300
// made a synthetic clip's schedule span 1e303 ms, and a huge width reached the driver as-is.
constexpr double kMinFps = 1.0;
constexpr double kMaxV4l2Fps = 10000.0;
constexpr double kMaxSyntheticFps = 2000.0;
constexpr int kMaxV4l2Side = 8192;
constexpr int kMaxSyntheticFrames = 1000000;
constexpr int kMaxSyntheticSide = 4096;

// A number in [lo, hi], the whole of `value`; `where` and `key` name it in the error.
double numberIn(const std::string& where, const std::string& key, const std::string& value,
                double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (!value.empty() && end == value.c_str() + value.size() && v >= lo && v <= hi) return v;
    throw ArgumentError(where + ": option " + key + "=" + value + " is not a number in " +
                        describeRange(lo, hi));
}

// A whole number in [lo, hi], the whole of `value`.
int wholeNumberIn(const std::string& where, const std::string& key, const std::string& value,
                  int lo, int hi) {
    int v = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
    if (ec == std::errc() && end == value.data() + value.size() && v >= lo && v <= hi) return v;
    throw ArgumentError(where + ": option " + key + "=" + value + " is not a whole number in " +
                        describeRange(lo, hi));
}

eyetrack::V4l2PixelFormat v4l2PixelFormat(const std::string& name) {
    if (name == "grey") return eyetrack::V4l2PixelFormat::Grey;
    if (name == "yuyv") return eyetrack::V4l2PixelFormat::Yuyv;
    if (name == "mjpeg") return eyetrack::V4l2PixelFormat::Mjpeg;
    throw ArgumentError("v4l2: unknown format '" + name + "' (grey | yuyv | mjpeg)");
}

eyetrack::V4l2Config v4l2Config(const SourceSpec& s) {
    eyetrack::V4l2Config c;
    c.device = s.target;
    const std::string where = "v4l2:" + s.target;
    for (const auto& [key, value] : s.options) {
        if (key == "width")
            c.width = wholeNumberIn(where, key, value, 1, kMaxV4l2Side);
        else if (key == "height")
            c.height = wholeNumberIn(where, key, value, 1, kMaxV4l2Side);
        else if (key == "fps")
            c.fps = numberIn(where, key, value, kMinFps, kMaxV4l2Fps);
        else if (key == "format")
            c.format = v4l2PixelFormat(value);
        else
            throw ArgumentError(where + ": unknown option '" + key +
                                "' (width, height, fps, format)");
    }
    return c;
}

eyetrack::EyeSimConfig syntheticConfig(const SourceSpec& s) {
    eyetrack::EyeSimConfig c;
    const std::string where = "synthetic:" + s.target;
    // from_chars, unlike stoull, refuses "-1" (which wrapped to 2^64 - 1) and leading blanks.
    const auto [end, ec] =
        std::from_chars(s.target.data(), s.target.data() + s.target.size(), c.seed);
    if (ec != std::errc() || end != s.target.data() + s.target.size())
        throw ArgumentError(where + ": the seed must be a whole number, 0 or more");
    for (const auto& [key, value] : s.options) {
        if (key != "preset" && key != "frames" && key != "fps" && key != "size")
            throw ArgumentError(where + ": unknown option '" + key +
                                "' (preset, frames, fps, size)");
    }
    auto option = [&](const std::string& key) -> const std::string* {
        const auto it = s.options.find(key);
        return it == s.options.end() ? nullptr : &it->second;
    };
    eyetrack::applyPreset(c, eyeSimPreset(option("preset") ? *option("preset") : "clean"));
    if (const auto* v = option("frames"))
        c.frames = wholeNumberIn(where, "frames", *v, 1, kMaxSyntheticFrames);
    if (const auto* v = option("fps"))
        c.fps = numberIn(where, "fps", *v, kMinFps, kMaxSyntheticFps);
    if (const auto* v = option("size")) {
        const auto x = v->find('x');
        if (x == std::string::npos)
            throw ArgumentError(where + ": size=" + *v + " is not WxH (32x24 to 4096x4096)");
        c.size = {wholeNumberIn(where, "size width", v->substr(0, x), 32, kMaxSyntheticSide),
                  wholeNumberIn(where, "size height", v->substr(x + 1), 24, kMaxSyntheticSide)};
    }
    return c;
}

} // namespace

SourceSpec splitSourceSpec(const std::string& spec) {
    const auto colon = spec.find(':');
    if (colon == std::string::npos || colon == 0)
        throw ArgumentError("frame source '" + spec +
                            "': expected v4l2:DEVICE, video:FILE, images:DIR or synthetic:SEED");
    SourceSpec s;
    s.scheme = spec.substr(0, colon);
    std::string rest = spec.substr(colon + 1);
    if (const auto q = rest.find('?');
        q != std::string::npos && s.scheme != "video" && s.scheme != "images") {
        splitQuery(spec, rest.substr(q + 1), s.options);
        rest = rest.substr(0, q);
    }
    if (rest.empty())
        throw ArgumentError("frame source '" + spec + "': nothing after '" + s.scheme + ":'");
    s.target = rest;
    return s;
}

eyetrack::FrameSourceConfig frameSourceConfig(const std::string& spec) {
    const SourceSpec s = splitSourceSpec(spec);
    if (s.scheme == "v4l2") return v4l2Config(s);
    if (s.scheme == "video") return eyetrack::VideoFileConfig{s.target};
    if (s.scheme == "images") return eyetrack::ImageFolderConfig{s.target, 30.0};
    if (s.scheme == "synthetic") return syntheticConfig(s);
    throw ArgumentError("frame source '" + spec + "': unknown kind '" + s.scheme +
                        "' (v4l2, video, images, synthetic)");
}

std::unique_ptr<eyetrack::FrameSource> openFrameSource(const std::string& spec) {
    return eyetrack::openFrameSource(frameSourceConfig(spec));
}

eyetrack::GazeModel gazeModel(const std::string& name) {
    if (name == "2d") return eyetrack::GazeModel::TwoD;
    if (name == "3d") return eyetrack::GazeModel::ThreeD;
    throw ArgumentError("unknown gaze model '" + name + "' (2d | 3d)");
}

eyetrack::EyeSimPreset eyeSimPreset(const std::string& name) {
    if (name == "clean") return eyetrack::EyeSimPreset::Clean;
    if (name == "hard") return eyetrack::EyeSimPreset::Hard;
    if (name == "wild") return eyetrack::EyeSimPreset::Wild;
    throw ArgumentError("unknown eyesim preset '" + name + "' (clean | hard | wild)");
}

eyetrack::PupilDetectorKind pupilDetectorKind(const std::string& name) {
    if (name == "starburst") return eyetrack::PupilDetectorKind::Starburst;
    if (name == "blob") return eyetrack::PupilDetectorKind::Blob;
    throw ArgumentError("unknown pupil detector '" + name + "' (starburst | blob)");
}

std::unique_ptr<eyetrack::GazeMapper>
gazeMapper(const eyetrack::EyeCalibration& eye, eyetrack::GazeModel model,
           const std::optional<eyetrack::CameraIntrinsics>& intrinsics) {
    if (model == eyetrack::GazeModel::ThreeD && !eye.model3d)
        throw ArgumentError("the calibration of eye '" + eye.eye +
                            "' has no 3D model: run gazetrace calibrate with --intrinsics "
                            "or --focal");
    return eyetrack::makeGazeMapper(eye, model, intrinsics);
}

} // namespace gt::app
