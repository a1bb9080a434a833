#include "gaze/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>

#include <opencv2/core.hpp>

#include "error.hpp"
#include "formats/atomic_file.hpp"
#include "formats/json_file.hpp"
#include "stats.hpp"

namespace gt::eyetrack {

std::vector<double> Calibration::features(cv::Point2d pupil) const {
    const double x = (pupil.x - mMean.x) / mScale.x, y = (pupil.y - mMean.y) / mScale.y;
    if (mX.size() == 4) return {1.0, x, y, x * y};
    return {1.0, x, y, x * y, x * x, y * y, x * x * y * y};
}

void Calibration::solve(const std::vector<CalibrationPoint>& points, int terms) {
    mX.assign(static_cast<std::size_t>(terms), 0.0);
    mY.assign(static_cast<std::size_t>(terms), 0.0);
    const int n = static_cast<int>(points.size());
    cv::Mat a(n, terms, CV_64F), bx(n, 1, CV_64F), by(n, 1, CV_64F);
    for (int i = 0; i < n; ++i) {
        const auto f = features(points[static_cast<std::size_t>(i)].pupil);
        for (int j = 0; j < terms; ++j)
            a.at<double>(i, j) = f[static_cast<std::size_t>(j)];
        const cv::Point2d angles = mDisplay.anglesDeg(points[static_cast<std::size_t>(i)].target);
        bx.at<double>(i) = angles.x;
        by.at<double>(i) = angles.y;
    }
    // The pupil positions must spread in both directions, or the system is degenerate.
    cv::Mat w;
    cv::SVD::compute(a, w, cv::SVD::NO_UV);
    if (w.at<double>(terms - 1) < 1e-6 * w.at<double>(0))
        throw CalibrationError(
            "calibration: pupil positions are degenerate (the eye did not move between targets?)");
    cv::Mat cx, cy;
    cv::solve(a, bx, cx, cv::DECOMP_SVD);
    cv::solve(a, by, cy, cv::DECOMP_SVD);
    for (int j = 0; j < terms; ++j) {
        mX[static_cast<std::size_t>(j)] = cx.at<double>(j);
        mY[static_cast<std::size_t>(j)] = cy.at<double>(j);
    }
    mUsed = n;
}

Calibration Calibration::fit(const std::vector<CalibrationPoint>& points,
                             const DisplayGeometry& display) {
    if (points.size() < 5)
        throw CalibrationError("calibration: need at least 5 targets with a detected pupil, got " +
                               std::to_string(points.size()));
    Calibration c;
    c.mDisplay = display;
    cv::Point2d mean(0, 0);
    for (const auto& p : points)
        mean += p.pupil;
    mean *= 1.0 / static_cast<double>(points.size());
    cv::Point2d spread(0, 0);
    for (const auto& p : points) {
        spread.x += (p.pupil.x - mean.x) * (p.pupil.x - mean.x);
        spread.y += (p.pupil.y - mean.y) * (p.pupil.y - mean.y);
    }
    spread.x = std::sqrt(spread.x / static_cast<double>(points.size()));
    spread.y = std::sqrt(spread.y / static_cast<double>(points.size()));
    if (spread.x < 1e-3 || spread.y < 1e-3)
        throw CalibrationError(
            "calibration: pupil positions are degenerate (the eye did not move between targets?)");
    c.mMean = mean;
    c.mScale = spread;

    auto termsFor = [](std::size_t n) { return n >= 9 ? 7 : 4; };
    c.solve(points, termsFor(points.size()));

    // One refit without an outlier (a target the viewer did not look at, a bad detection): for
    // each target, fit the others and see how well they agree among themselves; the target whose
    // removal leaves the most consistent fit is dropped if the others predict it badly (more than
    // max(3 x their median residual, 2 deg)). Judging by the others' fit rather than by the
    // target's own residual matters: a gross outlier bends a 7-term fit towards itself, and
    // with 9 targets a corner predicted from the rest is an extrapolation.
    std::size_t bestDrop = points.size();
    double bestSpread = 1e300, bestOwnResidual = 0.0, bestMedian = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::vector<CalibrationPoint> others;
        for (std::size_t k = 0; k < points.size(); ++k)
            if (k != i) others.push_back(points[k]);
        if (others.size() < 5) break;
        Calibration loo = c;
        try {
            loo.solve(others, termsFor(others.size()));
        } catch (const CalibrationError&) {
            continue;
        }
        std::vector<double> residuals;
        double othersSum = 0.0;
        for (const auto& p : others) {
            residuals.push_back(display.angularDistanceDeg(loo.map(p.pupil), p.target));
            othersSum += residuals.back();
        }
        if (othersSum < bestSpread) {
            bestSpread = othersSum;
            bestDrop = i;
            bestOwnResidual =
                display.angularDistanceDeg(loo.map(points[i].pupil), points[i].target);
            bestMedian = median(residuals);
        }
    }
    std::vector<CalibrationPoint> kept = points;
    if (bestDrop < points.size() && bestOwnResidual > std::max(3.0 * bestMedian, 2.0)) {
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(bestDrop));
        c.mDropped = 1;
    }
    c.solve(kept, termsFor(kept.size()));
    double sum = 0.0;
    for (const auto& p : kept)
        sum += display.angularDistanceDeg(c.map(p.pupil), p.target);
    c.mFitErrorDeg = sum / static_cast<double>(kept.size());
    return c;
}

cv::Point2d Calibration::map(cv::Point2d pupil) const {
    return mDisplay.pixelAtDeg(mapToAnglesDeg(pupil));
}

cv::Point2d Calibration::mapToAnglesDeg(cv::Point2d pupil) const {
    const auto f = features(pupil);
    cv::Point2d s(0, 0);
    for (std::size_t j = 0; j < f.size(); ++j) {
        s.x += mX[j] * f[j];
        s.y += mY[j] * f[j];
    }
    return s;
}

nlohmann::json Calibration::toJson() const {
    return {{"format", "gazetrace-calibration"},
            {"version", kVersion},
            {"model", mX.size() == 7 ? "poly7" : "poly4"},
            {"outputs", "gaze_angles_deg"}, // yaw, pitch of DisplayGeometry::anglesDeg
            {"display",
             {{"width_px", mDisplay.widthPx},
              {"height_px", mDisplay.heightPx},
              {"width_cm", mDisplay.widthCm},
              {"distance_cm", mDisplay.distanceCm}}},
            {"pupil_mean", {mMean.x, mMean.y}},
            {"pupil_scale", {mScale.x, mScale.y}},
            {"coefficients_x", mX},
            {"coefficients_y", mY},
            {"points_used", mUsed},
            {"outliers_dropped", mDropped},
            {"fit_error_deg", mFitErrorDeg}};
}

Calibration Calibration::fromJson(const nlohmann::json& j, const std::string& what) {
    auto bad = [&](const std::string& why) {
        return FormatError("calibration " + what + ": " + why);
    };
    if (!j.is_object()) throw bad("not a JSON object");
    // is_string first: value() throws a JSON type_error on a number (found by fuzzing).
    if (!j.contains("format") || !j["format"].is_string() ||
        j["format"].get<std::string>() != "gazetrace-calibration")
        throw bad("not a gazetrace calibration (\"format\" is missing or wrong)");
    if (!j.contains("version") || !j["version"].is_number_integer())
        throw bad("\"version\" is missing");
    // As the number it is (2^40 read through int was reported as "version 0").
    if (j["version"].get<long long>() != kVersion)
        throw bad("version " + std::to_string(j["version"].get<long long>()) +
                  " is not supported (expected " + std::to_string(kVersion) +
                  "; run gazetrace calibrate again)");
    // Every field typed and named: a wrong type or a missing field is one line naming it.
    Calibration c;
    const JsonFields fields(j, "calibration " + what);
    constexpr double kAny = std::numeric_limits<double>::max(); // finite; bounded below
    const std::string model = fields.text("model");
    const std::size_t terms = model == "poly7" ? 7 : model == "poly4" ? 4 : 0;
    if (terms == 0) throw bad("unknown model '" + model + "'");
    const JsonFields display(fields.at("display"), "calibration " + what, "display.");
    constexpr std::int64_t kMaxDisplayPx = 1 << 20;
    c.mDisplay.widthPx = static_cast<int>(display.integer("width_px", 1, kMaxDisplayPx));
    c.mDisplay.heightPx = static_cast<int>(display.integer("height_px", 1, kMaxDisplayPx));
    c.mDisplay.widthCm = display.number("width_cm", -kAny, kAny);
    c.mDisplay.distanceCm = display.number("distance_cm", -kAny, kAny);
    const auto mean = fields.numbers("pupil_mean", 2, -kAny, kAny);
    const auto scale = fields.numbers("pupil_scale", 2, -kAny, kAny);
    const auto coefficients = [&](const char* key) {
        const nlohmann::json& v = fields.at(key);
        if (!v.is_array() || v.size() != terms)
            throw bad("model " + model + " needs " + std::to_string(terms) +
                      " coefficients per axis");
        return fields.numbers(key, terms, -kAny, kAny);
    };
    c.mX = coefficients("coefficients_x");
    c.mY = coefficients("coefficients_y");
    c.mMean = {mean[0], mean[1]};
    c.mScale = {scale[0], scale[1]};
    constexpr std::int64_t kMaxInt = std::numeric_limits<int>::max();
    c.mUsed =
        fields.has("points_used") ? static_cast<int>(fields.integer("points_used", 0, kMaxInt)) : 0;
    c.mDropped = fields.has("outliers_dropped")
                     ? static_cast<int>(fields.integer("outliers_dropped", 0, kMaxInt))
                     : 0;
    c.mFitErrorDeg = fields.number("fit_error_deg", 0.0, 360.0, 0.0);
    const auto finite = [](const std::vector<double>& v) {
        return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
    };
    if (!finite(c.mX) || !finite(c.mY) || !(c.mScale.x > 0.0) || !(c.mScale.y > 0.0) ||
        c.mDisplay.widthPx <= 0 || c.mDisplay.heightPx <= 0 || !(c.mDisplay.widthCm > 0.0) ||
        !(c.mDisplay.distanceCm > 0.0))
        throw bad("values out of range (non-finite coefficients, or a non-positive scale or "
                  "display size)");
    // Finite is not enough: a coefficient of 1e308 or a scale of 1e-300 maps an ordinary pupil
    // to an infinite gaze (fuzz regression cases). What a fit produces: pupil means and spreads
    // in camera pixels, coefficients in degrees per unit of normalised feature. Within these
    // bounds the largest feature, ((1e5 + 1e5) / 1e-3)^4, times 1e6 stays finite.
    const auto within = [](const std::vector<double>& v, double limit) {
        return std::all_of(v.begin(), v.end(), [&](double x) { return std::abs(x) <= limit; });
    };
    if (!within(c.mX, 1e6) || !within(c.mY, 1e6) || !within({c.mMean.x, c.mMean.y}, 1e5) ||
        !(c.mScale.x >= 1e-3 && c.mScale.x <= 1e5 && c.mScale.y >= 1e-3 && c.mScale.y <= 1e5) ||
        !(c.mDisplay.widthCm <= 1e5 && c.mDisplay.distanceCm <= 1e5))
        throw bad("values out of range (coefficients beyond 1e6, a pupil mean beyond 1e5 px, a "
                  "pupil scale outside 1e-3..1e5 px or a display beyond 1 km)");
    return c;
}

void Calibration::save(const std::filesystem::path& file) const {
    AtomicFile out(file);
    out.stream() << toJson().dump(2) << "\n";
    out.commit();
}

Calibration Calibration::load(const std::filesystem::path& file) {
    const nlohmann::json j = readJsonFile(file, "calibration");
    // A version-3 file (gaze/calibration_set.hpp) with one eye: its polynomial.
    if (j.is_object() && j.contains("version") && j["version"].is_number_integer() &&
        j["version"].get<long long>() == 3 && j.contains("eyes") && j["eyes"].is_array()) {
        if (j["eyes"].size() == 1 && j["eyes"][0].is_object() && j["eyes"][0].contains("poly"))
            return fromJson(j["eyes"][0]["poly"], file.string());
        if (j["eyes"].size() == 2)
            throw FormatError(
                "calibration " + file.string() +
                ": holds two eyes, and this reads one (track both eyes with gazetrace track, "
                "emit the gaze over UDP and read it from there)");
    }
    return fromJson(j, file.string());
}

} // namespace gt::eyetrack
