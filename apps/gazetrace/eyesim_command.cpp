#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include <opencv2/videoio.hpp>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "eye_source_parsing.hpp"
#include "formats/atomic_file.hpp"
#include "formats/csv_tables.hpp"
#include "option_parsing.hpp"
#include "sim/synthetic_eye.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

cv::Size parseSize(const std::string& s) {
    const auto size = parseSizeText(s);
    if (!size || size->first < 32 || size->second < 24 || size->first > 4096 || size->second > 4096)
        throw ArgumentError("--size " + s + ": expected WxH between 32x24 and 4096x4096");
    return {static_cast<int>(size->first), static_cast<int>(size->second)};
}

// The clip's configuration from the options, each checked.
eyetrack::EyeSimConfig eyesimConfig(const EyesimOptions& o) {
    eyetrack::EyeSimConfig c;
    c.seed = o.seed;
    c.frames = o.frames;
    c.size = parseSize(o.size);
    c.fps = o.fps;
    c.schedule.calibrationPoints = o.grid;
    c.schedule.targetMs = o.targetMs;
    eyetrack::applyPreset(c, eyeSimPreset(o.preset));
    if (o.perspective) c.perspective = true;
    if (!o.slipMm.empty()) {
        double x = 0, y = 0, z = 0;
        char extra = 0;
        if (std::sscanf(o.slipMm.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &extra) != 3 ||
            !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || std::abs(x) > 20 ||
            std::abs(y) > 20 || std::abs(z) > 20)
            throw ArgumentError("--slip-mm " + o.slipMm + ": expected X,Y,Z in mm, each within 20");
        c.slipMm = {x, y, z};
        c.slipAtMs = std::max(0.0, o.slipAtMs);
    }
    if (!std::isfinite(o.slipDeg) || std::abs(o.slipDeg) > 20.0)
        throw ArgumentError("--slip-deg: expected a turn within 20 degrees");
    c.slipDeg = o.slipDeg;
    if (o.slipAtMs >= 0.0) c.slipAtMs = o.slipAtMs;
    if (o.eye != "cyclops" && o.eye != "left" && o.eye != "right" && o.eye != "both")
        throw ArgumentError("--eye " + o.eye + ": expected left, right or both");
    if (!(o.ipdMm >= 40.0 && o.ipdMm <= 80.0)) throw ArgumentError("--ipd-mm: expected 40..80 mm");
    if (!(o.depthCm == 0.0 || (o.depthCm >= 10.0 && o.depthCm <= 10000.0)))
        throw ArgumentError("--depth-cm: expected 10..10000 cm (0: on the screen)");
    c.fixationDepthCm = o.depthCm;
    return c;
}

// What the preset drew for this seed (wild draws its variations per seed), so a clip that
// scores badly can be told apart by what it shows.
nlohmann::json appearanceJson(const eyetrack::EyeSimConfig& c) {
    return {{"glints", c.glints},
            {"blur_sigma", c.blurSigma},
            {"noise_sigma", c.noiseSigma},
            {"upper_lid_height", c.upperLidHeight},
            {"drooping_lashes", c.droopingLashes},
            {"mascara", c.mascara},
            {"shadows", c.shadows},
            {"eyeliner", c.eyeliner},
            {"iris_contrast", c.irisContrast},
            {"border_glints", c.borderGlints},
            {"camera_tilt_deg", c.cameraTiltDeg},
            {"lower_lid_raise", c.lowerLidRaise},
            {"pupil_dilation", c.pupilDilation}};
}

} // namespace

nlohmann::json runEyesim(const EyesimOptions& o) {
    eyetrack::EyeSimConfig c = eyesimConfig(o);
    const bool both = o.eye == "both";
    if (both && o.truthRight.empty())
        throw ArgumentError("--eye both writes one frame with both eyes side by side and needs "
                            "--truth-right for the right eye's truth");
    // The left eye's look comes from the seed; the right eye's from a second seed, so the two
    // eyes of one clip differ as a person's do.
    eyetrack::EyeSimConfig left = c, right = c;
    left.eyeOffsetMm = -0.5 * o.ipdMm;
    right.eyeOffsetMm = 0.5 * o.ipdMm;
    right.appearanceSeed = o.seed * 7919 + 17;
    if (o.eye == "left") c = left;
    if (o.eye == "right") c = right;
    const eyetrack::SyntheticEye eye(both ? left : c);
    std::optional<eyetrack::SyntheticEye> second;
    if (both) second.emplace(right);
    const cv::Size frameSize(both ? 2 * c.size.width : c.size.width, c.size.height);

    const std::filesystem::path video(o.out);
    std::string ext = video.extension().string();
    if (ext != ".mkv" && ext != ".avi")
        throw ArgumentError("--out " + o.out + ": use .mkv or .avi (lossless FFV1)");
    std::error_code ec;
    if (video.has_parent_path() && !std::filesystem::is_directory(video.parent_path(), ec))
        throw ArgumentError("--out " + o.out + ": folder " + video.parent_path().string() +
                            " does not exist");
    // OpenCV writes the clip under a temporary name; it replaces --out only when the run ends.
    io::StagedFile staged(video);
    eyetrack::AtomicFile truth(o.truth);
    truth.stream() << eyetrack::truthHeader() << "\n";
    std::optional<eyetrack::AtomicFile> truthRight;
    if (both) {
        truthRight.emplace(o.truthRight);
        truthRight->stream() << eyetrack::truthHeader() << "\n";
    }
    {
        cv::VideoWriter writer(staged.temp().string(), cv::CAP_FFMPEG,
                               cv::VideoWriter::fourcc('F', 'F', 'V', '1'), c.fps, frameSize,
                               false);
        if (!writer.isOpened())
            throw ArgumentError("--out " + o.out + ": cannot open a lossless FFV1 writer");
        for (int f = 0; f < c.frames; ++f) {
            // SIGINT or SIGTERM: the clip and the truth are left unwritten (their destructors
            // remove the temporaries), an existing --out as it was.
            throwIfStopRequested();
            eyetrack::EyeTruth t;
            cv::Mat image = eye.render(f, &t);
            truth.stream() << eyetrack::truthRow(t) << "\n";
            if (second) {
                eyetrack::EyeTruth tr;
                const cv::Mat other = second->render(f, &tr);
                truthRight->stream() << eyetrack::truthRow(tr) << "\n";
                cv::hconcat(image, other, image);
            }
            writer.write(image);
        }
    }
    staged.commit();
    truth.commit();
    if (truthRight) truthRight->commit();
    if (!o.intrinsicsOut.empty()) eye.intrinsics().save(o.intrinsicsOut);
    nlohmann::json j{{"frames", c.frames}, {"width", frameSize.width}, {"height", frameSize.height},
                     {"fps", c.fps},       {"preset", o.preset},       {"seed", o.seed},
                     {"video", o.out},     {"truth", o.truth}};
    j["appearance"] = appearanceJson(c);
    if (o.eye != "cyclops") {
        j["eye"] = o.eye;
        j["ipd_mm"] = o.ipdMm;
    }
    if (both) {
        j["truth_right"] = o.truthRight;
        j["regions"] = cv::format("0,0,%d,%d;%d,0,%d,%d", c.size.width, c.size.height, c.size.width,
                                  c.size.width, c.size.height);
    }
    return j;
}

} // namespace gt::app
