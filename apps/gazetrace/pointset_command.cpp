#include "pointset_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <unistd.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "display/display_space.hpp"
#include "foveation/point_set_cache.hpp"
#include "option_parsing.hpp"
#include "scene/image_io.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

// A progress bar on stderr when it is a terminal; else a line every few seconds once the
// generation has run for a while (a log file or a test's pipe).
foveation::PointSet::Progress progressBar() {
    if (!isatty(STDERR_FILENO)) {
        auto step = std::make_shared<progress::Step>("pointset: generating the point set", 1000);
        return [step](double f) { (void)step->reach(f); };
    }
    return [](double f) {
        const int width = 40, filled = static_cast<int>(f * width);
        std::fprintf(stderr, "\rgenerating point set [%.*s%*s] %3d%%", filled,
                     "########################################", width - filled, "",
                     static_cast<int>(f * 100.0));
        if (f >= 1.0) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    };
}

// Figure 12: every point as a dark dot on white, at canvas resolution.
void drawPoints(const foveation::PointSet& set, const std::string& path) {
    const uint32_t w = set.canvasWidth(), h = set.canvasHeight();
    std::vector<uint8_t> px(static_cast<std::size_t>(w) * h * 4, 255);
    for (const foveation::Point& p : set.points()) {
        const auto x = static_cast<uint32_t>(p.x), y = static_cast<uint32_t>(p.y);
        if (x >= w || y >= h) continue;
        uint8_t* c = &px[(static_cast<std::size_t>(y) * w + x) * 4];
        c[0] = c[1] = c[2] = 0;
    }
    // The screen outline with the gaze centred, in red.
    const uint32_t sw = set.params().display.width, sh = set.params().display.height;
    for (uint32_t x = sw / 2; x < sw / 2 + sw; ++x) {
        for (uint32_t y : {sh / 2, sh / 2 + sh - 1}) {
            uint8_t* c = &px[(static_cast<std::size_t>(y) * w + x) * 4];
            c[0] = 220, c[1] = 30, c[2] = 30;
        }
    }
    for (uint32_t y = sh / 2; y < sh / 2 + sh; ++y) {
        for (uint32_t x : {sw / 2, sw / 2 + sw - 1}) {
            uint8_t* c = &px[(static_cast<std::size_t>(y) * w + x) * 4];
            c[0] = 220, c[1] = 30, c[2] = 30;
        }
    }
    image::writePngAtomic(path, w, h, px);
}

nlohmann::json describe(const foveation::CachedPointSet& c) {
    const foveation::PointSetStats s = c.set.stats(10.0f); // 10-pixel margin, thesis 4.2
    const double total = static_cast<double>(s.total);
    nlohmann::json j = {{"profile", c.set.params().display.name},
                        {"width", c.set.params().display.width},
                        {"height", c.set.params().display.height},
                        {"scale", c.set.params().scale},
                        {"seed", c.set.params().seed},
                        {"viewing_distance", c.set.params().display.viewingDistance},
                        {"total", s.total},
                        {"on_screen_centre", s.onScreenCentre},
                        {"on_screen_corner", s.onScreenCorner},
                        {"on_screen_centre_percent",
                         total > 0 ? 100.0 * static_cast<double>(s.onScreenCentre) / total : 0.0},
                        {"on_screen_corner_percent",
                         total > 0 ? 100.0 * static_cast<double>(s.onScreenCorner) / total : 0.0},
                        {"from_cache", c.fromCache},
                        {"seconds", c.seconds}};
    if (c.set.params().minSpacing > 0.0) j["spacing_floor"] = c.set.params().minSpacing;
    return j;
}

} // namespace

nlohmann::json runPointSet(const PointSetOptions& o) {
    foveation::PointSetParams params;
    std::optional<display::HmdProfile> hmd;
    if (!o.hmd.empty()) hmd = hmdProfile(o.hmd);
    params.display = hmd ? hmd->pointSetProfile : displayProfile(o.profile);
    params.seed = o.seed;
    const std::filesystem::path dir =
        o.cacheDir.empty() ? defaultCacheDir() : std::filesystem::path(o.cacheDir);
    for (const std::string& f : {o.out, o.image}) {
        if (f.empty()) continue;
        const std::filesystem::path parent = std::filesystem::path(f).parent_path();
        std::error_code ec;
        if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
            throw ArgumentError("cannot write " + f + ": folder " + parent.string() +
                                " does not exist");
        }
    }
    auto one = [&](double scale) {
        if (!(scale > 0.0) || scale > 100.0) throw ArgumentError("--scale must be in (0, 100]");
        throwIfStopRequested(); // each set of a sweep is a step of its own
        params.scale = scale;
        // The set a view of this display traces: thinned where the display is coarser than the
        // acuity model (point_set_cap.hpp).
        foveation::CachedPointSet c = foveation::loadOrGenerateForView(dir, params, progressBar());
        if (!c.warning.empty()) log::warn(c.warning);
        if (!c.thinned.empty()) log::info(c.thinned);
        return c;
    };
    if (!o.sweep.empty()) {
        // Figure 14: points in the set against the scaling value.
        nlohmann::json rows = nlohmann::json::array();
        for (double s : o.sweep)
            rows.push_back(describe(one(s)));
        return {{"profile", o.profile}, {"sweep", rows}};
    }
    const foveation::CachedPointSet c = one(o.scale);
    if (hmd) {
        // Where the rays go with the set laid in the image and laid on the panel, for the left
        // eye looking along its axis and at a quarter of the way from the top-left corner.
        const display::EyeTangents t = display::eyeTangents(*hmd, 0);
        const glm::vec2 centre = display::lensCentre(t);
        const glm::vec2 size(static_cast<float>(hmd->eyeWidth), static_cast<float>(hmd->eyeHeight));
        nlohmann::json rows = nlohmann::json::array();
        for (const glm::vec2 gaze : {centre * size, 0.25f * size}) {
            const display::LayoutComparison cmp =
                display::compareLayouts(c.set, gaze, hmd->lens, centre, 10.0f);
            rows.push_back({{"gaze_image", {gaze.x, gaze.y}},
                            {"gaze_panel", {cmp.gazePanel.x, cmp.gazePanel.y}},
                            {"image_points", cmp.imagePoints},
                            {"panel_points", cmp.panelPoints},
                            {"image_density_per_1000px", cmp.imageDensity},
                            {"panel_density_per_1000px", cmp.panelDensity}});
        }
        nlohmann::json j = describe(c);
        j["hmd"] = hmd->name;
        j["layouts"] = rows;
        return j;
    }
    throwIfStopRequested(); // a set generated at length, then the files
    if (!o.out.empty()) foveation::savePointSet(o.out, c.set);
    if (!o.image.empty()) drawPoints(c.set, o.image);
    nlohmann::json j = describe(c);
    if (!o.out.empty()) j["output"] = o.out;
    if (!o.image.empty()) j["image"] = o.image;
    return j;
}

} // namespace gt::app
