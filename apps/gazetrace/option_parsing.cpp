#include "option_parsing.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>

#include "core/error.hpp"

namespace gt::app {

render::Interpolation parseInterpolation(const std::string& name) {
    if (name == "nn") return render::Interpolation::Nearest;
    if (name == "msm") return render::Interpolation::Shepard;
    if (name == "rbf") return render::Interpolation::Rbf;
    throw ArgumentError("--interp: '" + name + "' is not available (known: nn, msm, rbf)");
}

render::RbfKernel parseKernel(const std::string& name) {
    if (name == "multiquadric") return render::RbfKernel::Multiquadric;
    if (name == "gaussian") return render::RbfKernel::Gaussian;
    throw ArgumentError("--kernel: '" + name +
                        "' is not available (known: multiquadric, gaussian)");
}

render::KnnIndex parseKnnIndex(const std::string& name) {
    if (name == "lists") return render::KnnIndex::NeighbourLists;
    if (name == "table") return render::KnnIndex::PixelTable;
    throw ArgumentError("--knn: '" + name + "' is not available (known: lists, table)");
}

render::Interpolation parseView(const std::string& name) {
    if (name == "points") return render::Interpolation::ViewPoints;
    if (name == "cells") return render::Interpolation::ViewCells;
    if (name == "eccentricity") return render::Interpolation::ViewSpacing;
    if (name == "motion") return render::Interpolation::ViewMotion;
    throw ArgumentError("--view: '" + name +
                        "' is not available (known: points, cells, eccentricity, motion)");
}

render::Reconstruction parseReconstruction(const std::string& name) {
    if (name == "thesis") return render::Reconstruction::Thesis;
    if (name == "gazetrace") return render::Reconstruction::Gazetrace;
    throw ArgumentError("--reconstruction: expected gazetrace or thesis, got '" + name + "'");
}

render::IntegratorSettings parseIntegrator(const IntegratorArgs& args) {
    render::IntegratorSettings s;
    if (args.integrator == "path") {
        s.integrator = render::Integrator::Path;
    } else if (args.integrator != "direct") {
        throw ArgumentError("--integrator: expected direct or path, got '" + args.integrator + "'");
    }
    if (args.bounces < 1 || args.bounces > trace::kMaxBounces) {
        throw ArgumentError("--bounces must be 1 to " + std::to_string(trace::kMaxBounces) +
                            ", got " + std::to_string(args.bounces));
    }
    s.bounces = args.bounces;
    if (args.sequence == "independent") {
        s.sequence = trace::SampleSequence::Independent;
    } else if (args.sequence != "sobol") {
        throw ArgumentError("--sequence: expected sobol or independent, got '" + args.sequence +
                            "'");
    }
    return s;
}

std::optional<passes::DenoiseSettings> parseDenoise(const IntegratorArgs& args) {
    using passes::DenoisePlacement;
    static const std::map<std::string, DenoisePlacement, std::less<>> kPlacements{
        {"on", passes::DenoiseSettings{}.placement},
        {"image", DenoisePlacement::Image},
        {"points", DenoisePlacement::Points},
        {"both", DenoisePlacement::Both}};
    if (args.denoise == "off") {
        return std::nullopt;
    }
    const auto it = kPlacements.find(args.denoise);
    if (it == kPlacements.end()) {
        throw ArgumentError("--denoise: expected off, on, image, points or both, got '" +
                            args.denoise + "'");
    }
    passes::DenoiseSettings s;
    s.placement = it->second;
    return s;
}

nlohmann::json integratorJson(const IntegratorArgs& args) {
    return {{"integrator", args.integrator},
            {"bounces", args.bounces},
            {"sequence", args.sequence},
            {"denoise", args.denoise},
            {"fovea_rays", args.foveaRays}};
}

double parseSlope(const std::string& text) {
    if (text == "A" || text == "a") {
        return foveation::kSlopeA;
    }
    if (text == "B" || text == "b") {
        return foveation::kSlopeB;
    }
    std::size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || text.empty() || !(v > 0.0) || !std::isfinite(v)) {
        throw ArgumentError("--slope: '" + text + "' (A, B or a positive MAR slope such as 0.03)");
    }
    return v;
}

std::string finiteNumberProblem(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size()) return "'" + text + "' is not a number";
    if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
    return "";
}

std::string nonNegativeIntegerProblem(const std::string& text) {
    const auto first = text.find_first_not_of(" \t");
    if (first != std::string::npos && text[first] == '-') {
        return "'" + text + "' is negative (expected 0 or more)";
    }
    return "";
}

std::optional<uint32_t> parseWholeNumber(const std::string& text) {
    uint32_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return v;
}

std::optional<std::pair<uint32_t, uint32_t>> parseSizeText(const std::string& text) {
    const auto x = text.find('x');
    if (x == std::string::npos) return std::nullopt;
    const auto w = parseWholeNumber(text.substr(0, x));
    const auto h = parseWholeNumber(text.substr(x + 1));
    if (!w || !h) return std::nullopt;
    return std::pair{*w, *h};
}

render::PresentMode parsePresentMode(const std::string& name) {
    if (name == "fifo") return render::PresentMode::Fifo;
    if (name == "mailbox") return render::PresentMode::Mailbox;
    if (name == "immediate") return render::PresentMode::Immediate;
    throw ArgumentError("--present: unknown mode '" + name + "' (known: fifo, mailbox, immediate)");
}

std::vector<std::string> hmdProfileNames() {
    std::vector<std::string> names;
    for (const display::HmdModel m : display::kHmdModels)
        names.push_back(display::hmdProfile(m).name);
    return names;
}

std::string hmdChoicesText(const char* separator) {
    std::string text;
    for (const std::string& name : hmdProfileNames())
        text += name + separator;
    return text + "custom:WxH@HFOVxVFOV[,HZ]";
}

render::HmdModel parseHmd(const std::string& name) {
    for (const display::HmdModel m : display::kHmdModels)
        if (display::hmdProfile(m).name == name) return m;
    throw ArgumentError("--hmd: unknown profile '" + name + "' (known: " + hmdChoicesText(", ") +
                        ")");
}

namespace {
// A number of the custom syntax: decimal digits with at most one point, nothing else (no sign,
// no exponent, no blanks).
std::optional<double> parseDecimal(const std::string& text) {
    if (text.empty() || text.find_first_not_of("0123456789.") != std::string::npos) {
        return std::nullopt;
    }
    double v = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return v;
}

// Splits `text` at the first `separator`: the part before it, and the part after (none when
// the separator is absent).
std::pair<std::string, std::optional<std::string>> splitAt(const std::string& text,
                                                           char separator) {
    const auto at = text.find(separator);
    if (at == std::string::npos) return {text, std::nullopt};
    return {text.substr(0, at), text.substr(at + 1)};
}
} // namespace

display::HmdProfile parseCustomHmd(const std::string& text) {
    const std::string what = "--hmd " + text + ": ";
    const auto syntax = [&] {
        return ArgumentError(what + "expected custom:WxH@HFOVxVFOV[,HZ], e.g. " +
                             "custom:3840x3744@120x105,90");
    };
    if (text.rfind(kCustomHmdPrefix, 0) != 0) throw syntax();
    const auto [size, rest] = splitAt(text.substr(std::string(kCustomHmdPrefix).size()), '@');
    if (!rest) throw syntax();
    const auto [fov, hzText] = splitAt(*rest, ',');
    const auto [hText, vText] = splitAt(fov, 'x');
    const auto pixels = parseSizeText(size);
    const std::optional<double> hfov = parseDecimal(hText);
    const std::optional<double> vfov = parseDecimal(vText.value_or(""));
    const std::optional<double> hz = hzText ? parseDecimal(*hzText) : std::optional(90.0);
    if (!pixels || !hfov || !vfov || !hz) throw syntax();
    const auto checkSize = [&](const char* name, uint32_t v) {
        if (v < kCustomHmdMinPixels || v > kCustomHmdMaxPixels) {
            throw ArgumentError(what + name + " " + std::to_string(v) + " pixels is outside " +
                                std::to_string(kCustomHmdMinPixels) + ".." +
                                std::to_string(kCustomHmdMaxPixels));
        }
    };
    checkSize("width", pixels->first);
    checkSize("height", pixels->second);
    const auto checkFov = [&](const char* name, const std::string& given, double v) {
        if (!(v > 0.0 && v < kCustomHmdMaxFovDeg)) {
            throw ArgumentError(what + name + " field of view " + given +
                                " degrees is outside (0, " +
                                std::to_string(static_cast<int>(kCustomHmdMaxFovDeg)) + ")");
        }
    };
    checkFov("horizontal", hText, *hfov);
    checkFov("vertical", vText.value_or(""), *vfov);
    if (!(*hz > 0.0) || !std::isfinite(*hz)) {
        throw ArgumentError(what + "refresh " + hzText.value_or("") + " Hz must be above 0");
    }
    return display::customHmdProfile(text, pixels->first, pixels->second, *hfov, *vfov, *hz);
}

display::HmdProfile hmdProfile(const std::string& name) {
    if (name.rfind(kCustomHmdPrefix, 0) == 0) return parseCustomHmd(name);
    return display::hmdProfile(parseHmd(name));
}

render::DisplayModel parseDisplay(const std::string& name) {
    if (name == "fove") return render::DisplayModel::Fove;
    if (name == "vive") return render::DisplayModel::Vive;
    if (name == "desktop") return render::DisplayModel::Desktop;
    throw ArgumentError("unknown display profile '" + name + "' (known: fove, vive, desktop)");
}

foveation::DisplayProfile displayProfile(const std::string& name) {
    return foveation::displayProfile(parseDisplay(name));
}

std::vector<std::string> displayProfileNames() {
    return {"fove", "vive", "desktop"};
}

std::filesystem::path defaultCacheDir() {
    if (const char* d = std::getenv("GAZETRACE_CACHE"); d && *d) return d;
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
        return std::filesystem::path(x) / "gazetrace";
    if (const char* h = std::getenv("HOME"); h && *h)
        return std::filesystem::path(h) / ".cache" / "gazetrace";
    return std::filesystem::temp_directory_path() / "gazetrace-cache";
}

namespace {
// `fallback`, or the environment variable `name`, which must then be a whole number from 1 to
// `most` in decimal digits: a typo (-5, 0, 1e99, 20M) is refused, not ignored, so a limit the
// user meant to raise is never silently the default.
std::uint64_t limitFromEnv(const char* name, std::uint64_t fallback, std::uint64_t most) {
    const char* env = std::getenv(name);
    if (!env) return fallback;
    const std::string text = env;
    std::uint64_t v = 0;
    bool digits = !text.empty() && text.size() <= 19;
    for (const char c : text) {
        digits = digits && c >= '0' && c <= '9';
        if (digits) v = v * 10 + static_cast<std::uint64_t>(c - '0');
    }
    if (!digits || v < 1 || v > most) {
        throw ArgumentError(std::string(name) + "=" + text + ": must be a whole number from 1 to " +
                            std::to_string(most));
    }
    return v;
}
} // namespace

vk::DeviceRequest parseDeviceRequest(const std::string& text) {
    vk::DeviceRequest r;
    const auto isDigit = [](unsigned char ch) { return std::isdigit(ch) != 0; };
    const bool numeric = !text.empty() && std::all_of(text.begin(), text.end(), isDigit);
    const bool negative =
        text.size() > 1 && text[0] == '-' && std::all_of(text.begin() + 1, text.end(), isDigit);
    if (numeric || negative) {
        // Every digit is read: a long number is an index out of range, not part of a name.
        std::size_t index = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
        if (negative || ec != std::errc() || end != text.data() + text.size() ||
            index > kMaxDeviceIndex) {
            throw ArgumentError("GAZETRACE_DEVICE=" + text + ": expected a device index 0.." +
                                std::to_string(kMaxDeviceIndex) +
                                " or part of a device's name (gazetrace devices lists them)");
        }
        r.index = index;
    } else {
        r.nameContains = text;
    }
    return r;
}

vk::DeviceRequest deviceRequest() {
    const char* device = std::getenv("GAZETRACE_DEVICE");
    return parseDeviceRequest(device ? device : "");
}

scene::GltfLoadOptions gltfLoadOptions() {
    scene::GltfLoadOptions o;
    // A billion triangles is ~100 GB of vertices; past it a value is a typo, not a scene.
    constexpr std::uint64_t kMostCount = 1'000'000'000;
    o.maxTriangles = static_cast<double>(limitFromEnv(
        "GAZETRACE_MAX_TRIANGLES", static_cast<std::uint64_t>(o.maxTriangles), kMostCount));
    o.maxInstances = static_cast<double>(limitFromEnv(
        "GAZETRACE_MAX_INSTANCES", static_cast<std::uint64_t>(o.maxInstances), kMostCount));
    o.maxTextureBytes =
        limitFromEnv("GAZETRACE_MAX_TEXTURE_BYTES", o.maxTextureBytes, std::uint64_t{1} << 40);
    const char* any = std::getenv("GAZETRACE_GLTF_ANY_PATH");
    o.anyPath = any != nullptr && std::string(any) == "1";
    return o;
}

std::pair<cv::Rect, cv::Rect> parseEyeRegions(const std::string& text) {
    int v[8] = {};
    char extra = 0;
    if (std::sscanf(text.c_str(), "%d,%d,%d,%d;%d,%d,%d,%d%c", &v[0], &v[1], &v[2], &v[3], &v[4],
                    &v[5], &v[6], &v[7], &extra) != 8) {
        throw ArgumentError("--regions " + text +
                            ": expected X,Y,W,H;X,Y,W,H (left eye; right eye)");
    }
    const cv::Rect l(v[0], v[1], v[2], v[3]), r(v[4], v[5], v[6], v[7]);
    for (const cv::Rect& q : {l, r}) {
        if (q.x < 0 || q.y < 0 || q.width < 32 || q.height < 24) {
            throw ArgumentError("--regions " + text +
                                ": each region must start at >= 0 and be at least 32x24");
        }
    }
    return {l, r};
}

eyetrack::UdpEndpoint parseUdpEndpoint(const std::string& url) {
    const std::string prefix = "udp://";
    auto bad = [&](const std::string& why) { return ArgumentError("--emit " + url + ": " + why); };
    if (url.rfind(prefix, 0) != 0) throw bad("expected udp://HOST:PORT");
    const std::string rest = url.substr(prefix.size());
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos) throw bad("expected udp://HOST:PORT");
    std::string host = rest.substr(0, colon);
    const std::string portText = rest.substr(colon + 1);
    int port = 0;
    try {
        std::size_t used = 0;
        port = std::stoi(portText, &used);
        if (used != portText.size()) port = 0;
    } catch (const std::exception&) {
        port = 0;
    }
    if (port <= 0 || port > 65535) throw bad("port must be 1-65535");
    if (host == "localhost") host = "127.0.0.1";
    if (host.empty() || host.find_first_not_of("0123456789.") != std::string::npos) {
        throw bad("host must be an IPv4 address or localhost");
    }
    return {host, static_cast<std::uint16_t>(port)};
}

} // namespace gt::app
