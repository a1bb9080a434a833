#include "layers_quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "eccentricity_layers.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/eccentricity_layers.hpp"
#include "frame_shots.hpp"
#include "full_resolution.hpp"
#include "method_choice.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "quality/eccentricity_bands.hpp"
#include "quality/resample.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"

namespace gt::app {

namespace {

using Image = std::vector<uint8_t>; // RGBA8, rows top first

using quality::kBandNames; // the eccentricity bands every picture-quality number is given in
using quality::kBands;

// Mean absolute difference (0-255) and PSNR (dB) per band.
nlohmann::json errorByBand(const Image& img, const Image& ref, const std::vector<uint8_t>& band) {
    std::array<double, kBands> abs{}, sq{};
    std::array<uint64_t, kBands> n{};
    for (std::size_t p = 0; p < band.size(); ++p) {
        for (int c = 0; c < 3; ++c) {
            const double d = static_cast<double>(img[4 * p + c]) - ref[4 * p + c];
            abs[band[p]] += std::abs(d);
            sq[band[p]] += d * d;
        }
        n[band[p]] += 3;
    }
    nlohmann::json out = nlohmann::json::object();
    for (std::size_t b = 0; b < kBands; ++b) {
        const double mse = n[b] ? sq[b] / static_cast<double>(n[b]) : 0.0;
        out[std::string(kBandNames[b])] = {
            {"mad", n[b] ? abs[b] / static_cast<double>(n[b]) : 0.0},
            {"psnr_db", mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0}};
    }
    return out;
}

// Share (%) of each band's pixels whose colour changed by more than 10/255 in any channel.
std::array<double, kBands> changedShare(const Image& a, const Image& b,
                                        const std::vector<uint8_t>& band) {
    std::array<uint64_t, kBands> changed{}, n{};
    for (std::size_t p = 0; p < band.size(); ++p) {
        bool c = false;
        for (int k = 0; k < 3; ++k) {
            c = c || std::abs(int(a[4 * p + k]) - int(b[4 * p + k])) > 10;
        }
        changed[band[p]] += c ? 1 : 0;
        ++n[band[p]];
    }
    std::array<double, kBands> out{};
    for (std::size_t i = 0; i < kBands; ++i) {
        out[i] = n[i] ? 100.0 * static_cast<double>(changed[i]) / static_cast<double>(n[i]) : 0.0;
    }
    return out;
}

// The uniform baseline's bilinear upscale.
Image upscaled(Image src, uint32_t sw, uint32_t sh, uint32_t w, uint32_t h) {
    return quality::upscale({sw, sh, std::move(src)}, w, h, quality::Upscale::Bilinear).pixels;
}

nlohmann::json bandsJson(const std::array<double, kBands>& v) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t b = 0; b < kBands; ++b) {
        j[std::string(kBandNames[b])] = v[b];
    }
    return j;
}

// The runs measureLayerQuality compares, on the desktop profile with the gaze centred: the
// layers, the point set and the uniform render at about equal rays, against a many-ray reference.
class LayerQualityRun {
public:
    explicit LayerQualityRun(const LayerQualityOptions& options)
        : o(options), desktop(foveation::displayProfile(foveation::DisplayModel::Desktop)),
          w(desktop.width), h(desktop.height),
          centre(0.5f * static_cast<float>(w), 0.5f * static_cast<float>(h)),
          bands(quality::bandMap(desktop, w, h, centre)), cache(cacheFolder(o.cacheDir)),
          renderer({.scene = o.scene}), shots(renderer) {
        base.camera = renderer.scene().camera;
        base.width = w;
        base.height = h;
        base.gaze = centre;
        base.post.taa = true;
        // The methods at about equal rays: layers at slope A (mean of two frames), the point
        // set at the scale whose on-screen points match them (1.5 on this profile), 1 ray per
        // point, nn, TAA; the uniform render at the resolution that spends the same rays,
        // upscaled.
        ls.display = desktop;
        layers.emplace(renderer.methodContext(), ls);
        pp.display = desktop;
        pp.scale = 1.5;
        points = makePointSetMethod(renderer, pp, o.cacheDir);
        points->settings.raysPerPoint = 1;
        points->settings.interpolation.method = passes::Interpolation::Nearest;
        uniform.emplace(renderer.methodContext(), passes::ReferenceSettings{1, 0});
        reference.emplace(renderer.methodContext(), passes::ReferenceSettings{refRays, 7});
    }

    // The still view: each method's error per band against the reference.
    nlohmann::json still() {
        render::View v = base;
        v.name = "reference";
        v.post.taa = false;
        const Image ref = shots.shot(v, *reference);
        Image layerImg, pointImg;
        uint64_t layerRays = 0, r1 = 0, r2 = 0;
        v = base;
        v.name = "layers";
        for (int i = 0; i < settle; ++i) {
            layerImg = shots.shot(v, *layers, i % 2 ? &r2 : &r1);
        }
        layerRays = (r1 + r2) / 2;
        v.name = "points";
        for (int i = 0; i < settle; ++i) {
            pointImg = shots.shot(v, *points);
        }
        const uint64_t pointRays = points->pointsSampled(centre);
        const double k = std::sqrt(static_cast<double>(w) * h / static_cast<double>(layerRays));
        uw = static_cast<uint32_t>(std::lround(w / k));
        uh = static_cast<uint32_t>(std::lround(h / k));
        v = base;
        v.name = "uniform";
        v.width = uw;
        v.height = uh;
        v.post.taa = false;
        const Image uniformImg = upscaled(shots.shot(v, *uniform), uw, uh, w, h);
        return {{"scene", o.scene},
                {"reference_rays_per_pixel", refRays},
                {"frames", settle},
                {"layers", {{"rays", layerRays}, {"bands", errorByBand(layerImg, ref, bands)}}},
                {"points",
                 {{"rays", pointRays},
                  {"scale", pp.scale},
                  {"bands", errorByBand(pointImg, ref, bands)}}},
                {"uniform",
                 {{"rays", static_cast<uint64_t>(uw) * uh},
                  {"size", {uw, uh}},
                  {"bands", errorByBand(uniformImg, ref, bands)}}}};
    }

    nlohmann::json moving() {
        // A moving camera: a dolly forward with a slow turn; per band, the share of pixels changing
        // by more than 10/255 between frames, against the reference's own (1 ray, same seed).
        const int moving = o.quick ? 4 : 12;
        std::vector<scene::CameraKey> keys;
        const scene::Camera c0 = renderer.scene().camera;
        for (int i = 0; i <= 1; ++i) {
            const glm::vec3 eye = c0.position + static_cast<float>(i) * 0.6f * c0.forward;
            const glm::vec3 target =
                eye + c0.forward + glm::vec3(0.15f * static_cast<float>(i), 0, 0);
            keys.push_back({static_cast<double>(i) * 1000.0, eye, target});
        }
        const scene::CameraPath path = scene::CameraPath::fromKeys(keys);
        nlohmann::json movingJson = nlohmann::json::object();
        render::FullResolution oneRay(renderer.methodContext(), {1, 3});
        for (const char* name : {"layers", "points", "uniform", "reference"}) {
            std::array<double, kBands> sum{};
            Image last;
            for (int i = 0; i < moving; ++i) {
                render::View mv = base;
                mv.name = std::string("moving_") + name;
                mv.camera = path.at(1000.0 * i / (moving - 1), c0.yfov);
                Image img;
                if (std::string(name) == "layers") {
                    img = shots.shot(mv, *layers);
                } else if (std::string(name) == "points") {
                    img = shots.shot(mv, *points);
                } else if (std::string(name) == "uniform") {
                    mv.width = uw;
                    mv.height = uh;
                    mv.post.taa = false;
                    img = upscaled(shots.shot(mv, *uniform), uw, uh, w, h);
                } else {
                    mv.post.taa = false;
                    img = shots.shot(mv, oneRay);
                }
                if (!last.empty()) {
                    const auto s = changedShare(img, last, bands);
                    for (std::size_t b = 0; b < kBands; ++b) {
                        sum[b] += s[b] / (moving - 1);
                    }
                }
                last = std::move(img);
            }
            movingJson[name] = bandsJson(sum);
        }
        return {{"frames", moving}, {"changed_percent", movingJson}};
    }

    nlohmann::json pursuit() {
        // Smooth pursuit over a still scene with subdivision cages, with and without geometric LOD:
        // the share of pixels changing by more than 10/255 from frame to frame (all bands).
        const int pursuitFrames = o.quick ? 6 : 24;
        render::Renderer lodRenderer({.scene = o.lodScene});
        FrameShots lodShots(lodRenderer);
        nlohmann::json pursuit = nlohmann::json::object();
        nlohmann::json traceGpu = nlohmann::json::object(); // median GPU ms of the tracing passes
        for (const bool lod : {false, true}) {
            render::EccentricityLayerSettings s = ls;
            s.lod = lod;
            render::EccentricityLayers lodLayers(lodRenderer.methodContext(), s);
            render::PointSetMethod lodPoints(lodRenderer.methodContext(), pp, cache);
            lodPoints.settings = points->settings;
            lodPoints.settings.lod = lod;
            for (const char* name : {"layers", "points"}) {
                double share = 0.0;
                std::vector<double> traceMs;
                Image last;
                for (int i = 0; i < pursuitFrames; ++i) {
                    render::View pv = base;
                    pv.camera = lodRenderer.scene().camera;
                    pv.name = std::string("pursuit_") + name + (lod ? "_lod" : "");
                    // content/gaze/pursuit.csv's target: a circle of 260 px radius once every 2 s,
                    // sampled at 90 Hz, here around the screen's centre.
                    const double a = 2.0 * 3.14159265358979 * (i / 90.0) / 2.0;
                    pv.gaze = centre + 260.0f * glm::vec2(static_cast<float>(std::cos(a)),
                                                          static_cast<float>(std::sin(a)));
                    const bool isLayers = std::string(name) == "layers";
                    const Image img =
                        isLayers ? lodShots.shot(pv, lodLayers) : lodShots.shot(pv, lodPoints);
                    if (i > 0) { // the first frame compiles and traces every layer
                        traceMs.push_back(lodShots.lastPassMs(isLayers ? "trace" : "point_sample"));
                    }
                    if (!last.empty()) {
                        const auto sh =
                            changedShare(img, last, std::vector<uint8_t>(bands.size(), 0));
                        share += sh[0] / (pursuitFrames - 1);
                    }
                    last = img;
                }
                pursuit[name][lod ? "lod" : "full_detail"] = share;
                std::sort(traceMs.begin(), traceMs.end());
                traceGpu[name][lod ? "lod" : "full_detail"] =
                    traceMs.empty() ? 0.0 : traceMs[traceMs.size() / 2];
            }
        }
        return {{"scene", o.lodScene},
                {"frames", pursuitFrames},
                {"lod_triangles", lodRenderer.lodTriangles()},
                {"changed_percent", pursuit},
                {"trace_gpu_ms_median", traceGpu}};
    }

    const LayerQualityOptions& o;
    const foveation::DisplayProfile desktop;
    const uint32_t w, h;
    const glm::vec2 centre;
    const std::vector<uint8_t> bands;
    const std::filesystem::path cache;
    const int settle = o.quick ? 4 : 16; // frames for the histories to converge
    const uint32_t refRays = o.quick ? 4 : 16;
    render::Renderer renderer;
    FrameShots shots;
    render::View base;
    render::EccentricityLayerSettings ls;
    foveation::PointSetParams pp;
    std::optional<render::EccentricityLayers> layers;
    std::unique_ptr<render::PointSetMethod> points;
    std::optional<render::FullResolution> uniform, reference;
    uint32_t uw = 0, uh = 0; // the uniform render's size (still())
};

} // namespace

nlohmann::json measureLayerQuality(const LayerQualityOptions& o) {
    LayerQualityRun run(o);
    nlohmann::json out;
    out["still"] = run.still();
    out["moving"] = run.moving();
    out["pursuit"] = run.pursuit();
    out["device"] = run.renderer.context().deviceName();
    return out;
}

void printLayerQuality(const nlohmann::json& q) {
    const auto& s = q["still"];
    std::printf("Still view, %s, mean abs error /255 and PSNR per band against %u rays/pixel "
                "(after %d frames):\n",
                s["scene"].get<std::string>().c_str(),
                s["reference_rays_per_pixel"].get<uint32_t>(), s["frames"].get<int>());
    for (const char* m : {"layers", "points", "uniform"}) {
        std::printf("  %-8s %8llu rays:", m,
                    static_cast<unsigned long long>(s[m]["rays"].get<uint64_t>()));
        for (const std::string_view name : kBandNames) {
            const std::string b(name);
            std::printf("  %s deg %5.2f (%4.1f dB)", b.c_str(),
                        s[m]["bands"][b]["mad"].get<double>(),
                        s[m]["bands"][b]["psnr_db"].get<double>());
        }
        std::printf("\n");
    }
    std::printf("Moving camera, %% of pixels changing > 10/255 per frame, per band:\n");
    for (const char* m : {"layers", "points", "uniform", "reference"}) {
        std::printf("  %-9s", m);
        for (const std::string_view name : kBandNames) {
            const std::string b(name);
            std::printf("  %s deg %5.2f", b.c_str(),
                        q["moving"]["changed_percent"][m][b].get<double>());
        }
        std::printf("\n");
    }
    const auto& t = q["pursuit"]["trace_gpu_ms_median"];
    std::printf("LOD savings on %s (triangles per level %s), median GPU ms of the tracing passes: "
                "layers %.1f -> %.1f, points %.1f -> %.1f\n",
                q["pursuit"]["scene"].get<std::string>().c_str(),
                q["pursuit"]["lod_triangles"].dump().c_str(),
                t["layers"]["full_detail"].get<double>(), t["layers"]["lod"].get<double>(),
                t["points"]["full_detail"].get<double>(), t["points"]["lod"].get<double>());
    const auto& p = q["pursuit"]["changed_percent"];
    std::printf(
        "Pursuit over %s, %% of pixels changing > 10/255 per frame: layers %.3f (LOD %.3f), "
        "points %.3f (LOD %.3f)\n",
        q["pursuit"]["scene"].get<std::string>().c_str(), p["layers"]["full_detail"].get<double>(),
        p["layers"]["lod"].get<double>(), p["points"]["full_detail"].get<double>(),
        p["points"]["lod"].get<double>());
}

} // namespace gt::app
