#pragma once
// How the image is rebuilt from the sampled points (thesis, 4.3): the settings pass `interpolate`
// rebuilds every pixel with and pass `rbf_solve` prepares RBF weights for, shared by both.
#include <cstdint>

#include "foveation/rbf_system.hpp"
#include "render_graph/render_graph.hpp"

namespace gt::foveation {

// Nearest/Shepard/RBF rebuild the image; the others are debug views of the point set
// (ViewMotion: each pixel's screen-space motion, nearest neighbour's).
enum class Interpolation { Nearest, Shepard, Rbf, ViewPoints, ViewCells, ViewSpacing, ViewMotion };
// The kernel type of the RBF builders, so that settings pass to them unconverted.
using RbfKernel = RbfKernelType;
// Where Modified Shepard and RBF find a pixel's k nearest points. PixelTable (the default): the
// thesis's table of the k nearest per canvas pixel, exact, 2-2.5x faster per frame than the
// lists on lavapipe, stored compactly (pixel_knn_table.hpp: 64 MB at k = 10 and 124 MB at
// k = 20 for fove, where flat it took 29.5 MB per neighbour) and seconds to build; RBF
// adds k floats per canvas pixel for its per-pixel weights (rbf_pixel_weights.hpp) and then
// costs no more than Modified Shepard. NeighbourLists: the nearest point per canvas pixel plus that
// point's 20 neighbours (75.6 MB for fove), exact at k <= 7 and close at k = 20; RBF then solves
// per point each frame (rbf_solve). Nearest neighbour always uses the nearest-point array (the
// thesis's table at k = 1).
enum class KnnIndex { NeighbourLists, PixelTable };

struct InterpolateSettings {
    Interpolation method = Interpolation::Nearest;
    uint32_t k = 10;
    float shepardPower = 2.0f;                  // 1: the thesis's eq. (6); 2: Renka's original
    RbfKernel kernel = RbfKernel::Multiquadric; // thesis eq. (10); Gaussian is eq. (9)
    float rbfShape = 1.0f;                      // c, in units of the point's spacing p
    KnnIndex knn = KnnIndex::PixelTable;        // where msm finds its k neighbours
    // Blend in display-referred space at this exposure (the view's): T(c) = c / (1 + e L(c)),
    // mapped back after (interpolate.comp). 0: linear radiance, as the thesis. Modified Shepard
    // and RBF with the pixel table; rbf_solve's per-point weights stay linear.
    float displayExposure = 0.0f;
    // Geometry-aware Modified Shepard: neighbours whose first-hit distance differs from the
    // nearest sample's by more than about this share of it lose their weight. 0: off (the
    // thesis).
    float edgeTolerance = 0.1f;
    // Colour-guided Modified Shepard: neighbours whose display-referred luminance differs from
    // the nearest sample's by more than about this lose their weight. 0: off (the thesis).
    float rangeSigma = 0.1f;
    // The frame whose moved sites point_sample traced (site_jitter.glsl), set per frame by the
    // method: Modified Shepard (and nearest neighbour, if given) blend from them. 0: the fixed
    // sites.
    uint32_t siteFrame = 0;
    float siteJitter = 0.0f; // how far they moved, as a share of their spacing
};

// The RBF weights rbf_solve wrote (one buffer per colour channel).
struct RbfWeights {
    rg::BufferId r, g, b;
};

// Modified Shepard or RBF reading the per-pixel k-NN table.
[[nodiscard]] inline bool usesPixelTable(const InterpolateSettings& s) {
    return s.knn == KnnIndex::PixelTable &&
           (s.method == Interpolation::Shepard || s.method == Interpolation::Rbf);
}

// Whether interpolate reads the point set's neighbour index (nearest point per canvas pixel,
// stored neighbours per point): every variant but Modified Shepard through the table, which
// takes its candidates from the table alone. RBF through the table falls back to the index
// where none of a pixel's k was sampled.
[[nodiscard]] inline bool readsNeighbourIndex(const InterpolateSettings& s) {
    return !(usesPixelTable(s) && s.method == Interpolation::Shepard);
}

// RBF over the neighbour lists: pass rbf_solve solves each point's weights every frame.
[[nodiscard]] inline bool usesRbfSolve(const InterpolateSettings& s) {
    return s.method == Interpolation::Rbf && s.knn == KnnIndex::NeighbourLists;
}

} // namespace gt::foveation
