#pragma once
// The perception model of the foveated ray-tracing thesis (section 4.1), after Wang et al. 2001
// with the parameters Geisler & Perry 1998 fitted:
//   eccentricity      e  = atan(d / (N v))               [deg]        thesis eq. (1)
//   cut-off frequency fc = e2 ln(1/CT0) / ((e + e2) a)   [cycles/deg] thesis eq. (2)
//   display Nyquist   fd = pi N v / 360                  [cycles/deg] thesis eq. (3)
//   point spacing     p  = fd / min(fd, fc) - (1 - sqrt(1/pi))   [px] thesis eq. (4)
// d is the distance from the centre of interest in pixels, N the display width in pixels and
// v the viewing distance in display widths. The eccentricity is multiplied by the point set's
// scaling value before eq. (2), which is how the thesis makes sparser sets (section 4.1).
#include <cstdint>
#include <string>

namespace gt::foveation {

struct DisplayProfile {
    std::string name;
    uint32_t width = 0;           // per-eye pixels
    uint32_t height = 0;          // per-eye pixels
    double viewingDistance = 1.0; // v, in display widths
};

// fove: 1280x1440 per eye (the thesis's FOVE HMD), v chosen to reproduce Table 1 (see the
// README, "Point set"); vive: 1080x1200 per eye; desktop: 1920x1080, 51 cm wide seen from
// 59 cm (Guenter et al. 2012's setup), v = 59 / 51.
enum class DisplayModel { Fove, Vive, Desktop };
[[nodiscard]] DisplayProfile displayProfile(DisplayModel model);
// A window of `width` x `height` pixels on the screen of `screen` (same pixel pitch, same viewing
// distance): the profile a point set for that window needs, with the screen's pixels per degree.
// v is in display widths, so it grows as the window narrows: v = v_screen * N_screen / N_window.
// A display whose `width` pixels span `horizontalFovDeg` about its centre, as a headset's eye
// image does: at the image's edge (d = N / 2) thesis eq. (1) must give half the field of view,
// so v = 1 / (2 tan(HFOV / 2)) image widths. Throws gt::ArgumentError unless 0 < HFOV < 180.
[[nodiscard]] DisplayProfile fovDisplayProfile(std::string name, uint32_t width, uint32_t height,
                                               double horizontalFovDeg);
[[nodiscard]] DisplayProfile windowProfile(const DisplayProfile& screen, uint32_t width,
                                           uint32_t height);

struct ContrastSensitivity {
    double ct0 = 1.0 / 64.0; // minimum contrast threshold
    double alpha = 0.106;    // spatial frequency decay constant
    double e2 = 2.3;         // half-resolution eccentricity [deg]

    // thesis eq. (1), times the scaling value.
    [[nodiscard]] static double eccentricityDeg(double distancePx, double displayWidthPx,
                                                double viewingDistance, double scale = 1.0);
    // thesis eq. (2).
    [[nodiscard]] double cutoffFrequency(double eccentricityDeg) const;
    // thesis eq. (3).
    [[nodiscard]] static double displayNyquist(double displayWidthPx, double viewingDistance);
    // thesis eq. (4): the Poisson-disc spacing in pixels at `distancePx` from the centre.
    [[nodiscard]] double spacing(double distancePx, const DisplayProfile& display,
                                 double scale = 1.0) const;
};

} // namespace gt::foveation
