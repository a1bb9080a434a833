#include "model/eye_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "error.hpp"
#include "stats.hpp"

namespace gt::eyetrack {

EyeModel::EyeModel(CameraIntrinsics camera, EyeModelConfig config)
    : mCamera(camera), mConfig(config) {
    if (!mCamera.valid()) {
        throw EyetrackError("eye model: camera intrinsics are not valid");
    }
    if (mConfig.window < mConfig.minObservations || mConfig.minObservations < 3) {
        throw EyetrackError("eye model: the window must hold at least minObservations (>= 3)");
    }
}

cv::Point2d EyeModel::project(const cv::Vec3d& p) const {
    return mCamera.project(p);
}

void EyeModel::add(const cv::RotatedRect& ellipse) {
    Observation o;
    try {
        o.circles = unprojectEllipse(ellipse, mCamera, mConfig.pupilRadiusMm);
    } catch (const EyetrackError&) {
        return; // a degenerate ellipse adds nothing
    }
    const Circle3d& c = o.circles[0];
    o.centre2d = project(c.centre);
    const cv::Point2d tip = project(c.centre + c.normal * (0.5 * mConfig.pupilRadiusMm));
    const cv::Point2d d = tip - o.centre2d;
    const double len = std::hypot(d.x, d.y);
    // A pupil facing the camera squarely has no image direction: it cannot place the centre.
    if (len < 1e-3) {
        return;
    }
    o.direction = d * (1.0 / len);
    mWindow.push_back(o);
    while (static_cast<int>(mWindow.size()) > mConfig.window) {
        mWindow.pop_front();
    }
    if (++mSinceFit >= mConfig.refitEvery &&
        static_cast<int>(mWindow.size()) >= mConfig.minObservations) {
        (void)fit();
    }
}

bool EyeModel::fit() {
    mSinceFit = 0;
    const int n = static_cast<int>(mWindow.size());
    if (n < mConfig.minObservations) {
        return false;
    }
    // Spread of the normals: the lines must not be (nearly) parallel.
    {
        cv::Vec3d mean(0, 0, 0);
        for (const auto& o : mWindow) {
            mean += o.circles[0].normal;
        }
        mean = cv::normalize(mean);
        double maxDeg = 0.0;
        for (const auto& o : mWindow) {
            const double c = std::clamp(o.circles[0].normal.dot(mean), -1.0, 1.0);
            maxDeg = std::max(maxDeg, std::acos(c) * 180.0 / std::numbers::pi);
        }
        if (2.0 * maxDeg < mConfig.minSpreadDeg) {
            return false;
        }
    }
    // 2. Least-squares intersection of the image lines, twice: the second time without the lines
    //    that pass far from the first estimate (ellipses from before a slip, bad fits).
    std::vector<char> use(static_cast<std::size_t>(n), 1);
    cv::Point2d x;
    for (int pass = 0; pass < 2; ++pass) {
        cv::Matx22d a = cv::Matx22d::zeros();
        cv::Vec2d b(0, 0);
        for (int i = 0; i < n; ++i) {
            if (!use[static_cast<std::size_t>(i)]) {
                continue;
            }
            const auto& o = mWindow[static_cast<std::size_t>(i)];
            const cv::Matx22d p(1 - o.direction.x * o.direction.x, -o.direction.x * o.direction.y,
                                -o.direction.x * o.direction.y, 1 - o.direction.y * o.direction.y);
            a += p;
            b += p * cv::Vec2d(o.centre2d.x, o.centre2d.y);
        }
        cv::Vec2d sol;
        if (!cv::solve(a, b, sol, cv::DECOMP_SVD)) {
            return false;
        }
        x = {sol[0], sol[1]};
        if (pass == 1) {
            break;
        }
        std::vector<double> dist(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
            const auto& o = mWindow[static_cast<std::size_t>(i)];
            const cv::Point2d r = x - o.centre2d;
            dist[static_cast<std::size_t>(i)] = std::abs(r.x * o.direction.y - r.y * o.direction.x);
        }
        const double cut = std::max(2.0, 3.0 * median(dist));
        for (int i = 0; i < n; ++i) {
            use[static_cast<std::size_t>(i)] = dist[static_cast<std::size_t>(i)] <= cut;
        }
    }
    // 3. The pupil of each ellipse: the circle whose normal points away from the centre.
    std::vector<const Circle3d*> pupils;
    for (int i = 0; i < n; ++i) {
        if (!use[static_cast<std::size_t>(i)]) {
            continue;
        }
        const auto& o = mWindow[static_cast<std::size_t>(i)];
        const cv::Point2d away = o.centre2d - x;
        const Circle3d* best = nullptr;
        double bestDot = -1e300;
        for (const Circle3d& c : o.circles) {
            const cv::Point2d dir = project(c.centre + c.normal * 0.5) - project(c.centre);
            const double dot = dir.dot(away) / std::max(1e-9, std::hypot(dir.x, dir.y));
            if (dot > bestDot) {
                bestDot = dot;
                best = &c;
            }
        }
        pupils.push_back(best);
    }
    if (pupils.size() < static_cast<std::size_t>(mConfig.minObservations) / 2) {
        return false;
    }
    // 4. The centre C and radius R: each pupil's centre is C + R n_i and lies on the camera ray
    //    d_i through it, so (I - d_i d_i^T)(C + R n_i) = 0. With R as the unit this is linear in
    //    C alone and uses only directions (the ray and the normal), not the circles' positions,
    //    which scale with the pupil's true size against the assumed one and so disagree as the
    //    pupil dilates. The scale is then set by the assumed radius at the pupils' median depth.
    cv::Matx33d a3 = cv::Matx33d::zeros();
    cv::Vec3d b3(0, 0, 0);
    for (const Circle3d* c : pupils) {
        const cv::Vec3d d = cv::normalize(c->centre);
        const cv::Matx33d p = cv::Matx33d::eye() - d * d.t();
        a3 += p;
        b3 -= p * c->normal;
    }
    cv::Vec3d unitCentre;
    if (!cv::solve(a3, b3, unitCentre, cv::DECOMP_SVD) || !(unitCentre[2] > 0.0)) {
        return false;
    }
    // Metric scale: the pupils' centres (at the assumed radius) against the unit model's.
    std::vector<double> scales;
    scales.reserve(pupils.size());
    for (const Circle3d* c : pupils) {
        const cv::Vec3d d = cv::normalize(c->centre);
        const cv::Vec3d p = unitCentre + c->normal; // the pupil in the unit model
        scales.push_back(cv::norm(c->centre) / std::max(1e-9, p.dot(d)));
    }
    const double scale = median(scales);
    const cv::Vec3d centre = unitCentre * scale;
    const double radius = scale;
    if (!(radius > 0.0) || !std::isfinite(radius) || !(centre[2] > 0.0)) {
        return false;
    }
    mCentre = centre;
    mRadius = radius;
    mReady = true;
    return true;
}

std::optional<cv::Vec3d> EyeModel::gaze(const cv::RotatedRect& ellipse) const {
    if (!mReady) {
        return std::nullopt;
    }
    std::array<Circle3d, 2> circles;
    try {
        circles = unprojectEllipse(ellipse, mCamera, mConfig.pupilRadiusMm);
    } catch (const EyetrackError&) {
        return std::nullopt;
    }
    // 5. The camera ray through the pupil's centre (both circles' centres lie on nearly the
    //    same ray; their mean) meets the sphere; the nearer intersection faces the camera.
    const cv::Vec3d d =
        cv::normalize(cv::normalize(circles[0].centre) + cv::normalize(circles[1].centre));
    const double b = d.dot(mCentre);
    const double disc = b * b - (mCentre.dot(mCentre) - mRadius * mRadius);
    // A ray that misses the sphere (noise at the rim): the point of the ray closest to it.
    const double t = disc >= 0.0 ? b - std::sqrt(disc) : b;
    const cv::Vec3d axis = d * t - mCentre;
    const double len = cv::norm(axis);
    if (!(len > 0.0)) {
        return std::nullopt;
    }
    return axis * (1.0 / len);
}

nlohmann::json EyeModel::toJson() const {
    return {{"centre_mm", {mCentre[0], mCentre[1], mCentre[2]}},
            {"radius_mm", mRadius},
            {"assumed_pupil_radius_mm", mConfig.pupilRadiusMm}};
}

void EyeModel::setSphere(const cv::Vec3d& centre, double radius) {
    if (!(radius > 0.0) || !(centre[2] > 0.0)) {
        throw EyetrackError("eye model: the sphere must be in front of the camera");
    }
    mCentre = centre;
    mRadius = radius;
    mReady = true;
}

} // namespace gt::eyetrack
