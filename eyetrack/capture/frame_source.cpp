#include "capture/frame_source.hpp"

#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "capture/file_sources.hpp"
#include "capture/v4l2_source.hpp"
#include "error.hpp"

namespace gt::eyetrack {

SourceSpec parseSourceSpec(const std::string& spec) {
    const auto colon = spec.find(':');
    if (colon == std::string::npos || colon == 0)
        throw CaptureError("frame source '" + spec +
                           "': expected v4l2:DEVICE, video:FILE, images:DIR or synthetic:SEED");
    SourceSpec s;
    s.scheme = spec.substr(0, colon);
    std::string rest = spec.substr(colon + 1);
    if (const auto q = rest.find('?');
        q != std::string::npos && s.scheme != "video" && s.scheme != "images") {
        std::string query = rest.substr(q + 1);
        rest = rest.substr(0, q);
        std::size_t pos = 0;
        while (pos <= query.size()) {
            const auto amp = query.find('&', pos);
            const std::string item =
                query.substr(pos, amp == std::string::npos ? std::string::npos : amp - pos);
            if (!item.empty()) {
                const auto eq = item.find('=');
                if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
                    throw CaptureError("frame source '" + spec + "': option '" + item +
                                       "' is not key=value");
                s.options[item.substr(0, eq)] = item.substr(eq + 1);
            }
            if (amp == std::string::npos) break;
            pos = amp + 1;
        }
    }
    if (rest.empty())
        throw CaptureError("frame source '" + spec + "': nothing after '" + s.scheme + ":'");
    s.target = rest;
    return s;
}

cv::Mat toGrey(const cv::Mat& image) {
    cv::Mat m = image;
    if (m.depth() == CV_16U)
        m.convertTo(m, CV_8U, 1.0 / 257.0);
    else if (m.depth() != CV_8U)
        throw CaptureError("frame has an unsupported pixel depth");
    cv::Mat grey;
    switch (m.channels()) {
    case 1:
        grey = m.clone();
        break;
    case 3:
        cv::cvtColor(m, grey, cv::COLOR_BGR2GRAY);
        break;
    case 4:
        cv::cvtColor(m, grey, cv::COLOR_BGRA2GRAY);
        break;
    default:
        throw CaptureError("frame has an unsupported number of channels");
    }
    return grey;
}

namespace {

double positiveOption(const SourceSpec& s, const std::string& key, double fallback) {
    const auto it = s.options.find(key);
    if (it == s.options.end()) return fallback;
    try {
        std::size_t used = 0;
        const double v = std::stod(it->second, &used);
        if (used == it->second.size() && v > 0.0) return v;
    } catch (const std::exception&) {
    }
    throw CaptureError(s.scheme + ":" + s.target + ": option " + key + "=" + it->second +
                       " is not a positive number");
}

} // namespace

std::unique_ptr<FrameSource> openFrameSource(const std::string& spec) {
    const SourceSpec s = parseSourceSpec(spec);
    if (s.scheme == "v4l2")
        return std::make_unique<V4l2Source>(v4l2ConfigFromSpec(s), V4l2Syscalls::system());
    if (s.scheme == "video") return std::make_unique<VideoFileSource>(s.target);
    if (s.scheme == "images") return std::make_unique<ImageFolderSource>(s.target, 30.0);
    if (s.scheme == "synthetic") {
        EyeSimConfig c;
        try {
            std::size_t used = 0;
            c.seed = std::stoull(s.target, &used);
            if (used != s.target.size()) throw std::invalid_argument(s.target);
        } catch (const std::exception&) {
            throw CaptureError("synthetic:" + s.target + ": the seed must be a whole number");
        }
        for (const auto& [key, value] : s.options) {
            if (key != "preset" && key != "frames" && key != "fps" && key != "size")
                throw CaptureError("synthetic:" + s.target + ": unknown option '" + key +
                                   "' (preset, frames, fps, size)");
        }
        applyPreset(c, s.options.count("preset") ? s.options.at("preset") : "clean");
        c.frames = static_cast<int>(positiveOption(s, "frames", c.frames));
        c.fps = positiveOption(s, "fps", c.fps);
        if (const auto it = s.options.find("size"); it != s.options.end()) {
            int w = 0, h = 0;
            char x = 0;
            if (std::sscanf(it->second.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 32 ||
                h < 24)
                throw CaptureError("synthetic:" + s.target + ": size=" + it->second +
                                   " is not WxH (at least 32x24)");
            c.size = {w, h};
        }
        return std::make_unique<SyntheticSource>(c);
    }
    throw CaptureError("frame source '" + spec + "': unknown kind '" + s.scheme +
                       "' (v4l2, video, images, synthetic)");
}

} // namespace gt::eyetrack
