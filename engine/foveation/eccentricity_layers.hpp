#pragma once
// Eccentricity layers (Guenter et al. 2012, section 4.3): a few nested layers around
// the gaze, each sampled at the coarsest pitch the eye still resolves at its inner edge, chosen
// to minimise the pixels rendered.
//   MAR model           omega = m e + omega0                         [deg/cycle]  eq. (1)
//   sampling factors    s1 = 1, s(i+1) = (m e_i + omega0) / omega*                 eq. (2)
//   layer diameters     D_i = 2 V* tan(e_i) D* / (s_i W*),  D_n = D* / s_n  [px]    eq. (3)
//   layer pixels        P_i = D_i^2,  P_n = alpha* D_n^2                           eq. (4)
//   total work          P = sum w_i P_i                                            eq. (5)
//   display radius      e* = atan(W* / (2 V*))                                     eq. (6)
//   display sharpness   omega* = atan(2 W* / (V* D*))                              eq. (7)
//   display pixels      P* = alpha* D*^2                                           eq. (8)
// The paper assumes a landscape display (alpha* <= 1) and says to measure width and resolution
// along the longer, vertical axis of a portrait one (its footnote 8): LayerDisplay does that, so
// fove's 1280 x 1440 eye image takes D* = 1440 and alpha* = 1280 / 1440.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "foveation/contrast_sensitivity.hpp"

namespace gt::foveation {

// The MAR slopes the paper's user study found (section 5): quality A, "neither degraded nor
// enhanced over a short ramp" (j = 12), and the more conservative B, "equivalent to the
// non-foveated reference" (j = 15).
inline constexpr double kSlopeA = 0.0275; // 1.65 arc minutes per degree
inline constexpr double kSlopeB = 0.0220; // 1.32 arc minutes per degree
// Average foveal acuity of adults below 50, 48 cycles per degree (section 3).
inline constexpr double kOmega0Deg = 1.0 / 48.0;

// eq. (1): minimum angle of resolution (degrees per cycle) at eccentricity e.
struct MarModel {
    double slope = kSlopeA;
    double omega0Deg = kOmega0Deg;
    [[nodiscard]] double marDeg(double eccentricityDeg) const noexcept {
        return slope * eccentricityDeg + omega0Deg;
    }
};

// The display as the paper describes it: resolution D* and physical width W* along the long
// axis, viewing distance V* (same unit as W*) and aspect alpha* = short / long <= 1.
struct LayerDisplay {
    double resolution = 1920.0; // D*
    double width = 51.0;        // W*
    double distance = 59.0;     // V*
    double aspect = 9.0 / 16.0; // alpha*

    // The paper's monitor (section 5): V* = 59 cm, W* = 51 cm, D* = 1920, alpha* = 9/16.
    [[nodiscard]] static LayerDisplay paperMonitor();
    // A gazetrace display profile: v is in display widths, pixels are square; portrait profiles
    // take the long (vertical) axis.
    [[nodiscard]] static LayerDisplay fromProfile(const DisplayProfile& profile);
    // A pinhole image of `longPixels` x `shortPixels` whose long axis spans `tangentExtent`
    // (tan of one edge to tan of the other) at unit distance: a view's frustum.
    [[nodiscard]] static LayerDisplay fromTangents(double longPixels, double shortPixels,
                                                   double tangentExtent);
    // Figure 12's display: field of view 2 e*, aspect 3/4 and exactly foveal sharpness
    // (omega* = omega0), so D* follows from eq. (9), D* = 4 tan(e*) / tan(omega0).
    [[nodiscard]] static LayerDisplay acuityMatched(double fieldOfViewDeg, double aspect = 0.75,
                                                    double omega0Deg = kOmega0Deg);

    [[nodiscard]] double radiusDeg() const;    // e*, eq. (6)
    [[nodiscard]] double sharpnessDeg() const; // omega*, eq. (7)
    [[nodiscard]] double pixels() const;       // P*, eq. (8)
    // Display pixels (long axis) per unit tangent at unit distance: D* V* / W*.
    [[nodiscard]] double pixelsPerTangent() const { return resolution * distance / width; }
};

struct Layer {
    double radiusDeg = 0.0;      // e_i (e* for the outer layer)
    double samplingFactor = 1.0; // s_i, eq. (2): layer pixel pitch in display pixels
    double diameter = 0.0;       // D_i, eq. (3), layer pixels along the long axis
    double pixels = 0.0;         // P_i, eq. (4)
    double weight = 1.0;         // w_i of eq. (5)
};

struct LayerPlan {
    std::vector<Layer> layers;  // inner first; the last covers the whole display
    double work = 0.0;          // P, eq. (5)
    double displayPixels = 0.0; // P*, eq. (8)
    [[nodiscard]] double speedup() const { return displayPixels / work; } // P* / P
};

// eqs. (2)-(5) for given inner radii 0 < e_1 < ... < e_(n-1) < e* (n = radii + 1 layers).
// `weights` is empty (all 1) or one per layer. Throws ArgumentError on radii out of order.
[[nodiscard]] LayerPlan planLayers(const LayerDisplay& display, const MarModel& mar,
                                   std::span<const double> radiiDeg,
                                   std::span<const double> weights = {});

// The brute-force minimisation of eq. (5) over the n - 1 radii on a grid of `steps` equal
// divisions of (0, e*) (section 4.3). n = 1 is the plain display. Throws for n outside 1..4.
[[nodiscard]] LayerPlan optimiseLayers(const LayerDisplay& display, const MarModel& mar,
                                       uint32_t layerCount, std::span<const double> weights = {},
                                       uint32_t steps = 400);

// The paper's half-rate weighting (w1 = 1, w_i = 1/2 for i > 1) for n layers.
[[nodiscard]] std::vector<double> halfRateWeights(uint32_t layerCount);

} // namespace gt::foveation
