#pragma once
// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild 2020, "FLIP: A
// Difference Evaluator for Alternating Images"): the per-pixel difference an observer sees when
// flipping between a reference and a test image, in [0, 1], for a viewer at a given number of
// pixels per degree of visual angle.
//
// Colour pipeline: sRGB -> linear -> XYZ -> the opponent space YCxCz; each channel blurred by
// its contrast-sensitivity filter (a sum of Gaussians whose width follows the pixels per
// degree, so detail finer than the eye resolves at that distance is removed); back to linear
// RGB clamped to the unit cube; CIELAB with the Hunt adjustment (chroma scaled by 0.01 L); the
// HyAB distance |dL| + ||(da, db)||, raised to qc = 0.7 and spread over [0, 1] so that the
// largest distance (green against blue) is 1 and pc = 0.4 of it maps to pt = 0.95.
// Feature pipeline: on the luminance, first (edge) and second (point) derivatives of a Gaussian
// of standard deviation 0.5 * 0.082 deg; the larger difference of their magnitudes, scaled by
// 1/sqrt(2) and raised to qf = 0.5, is df. Result: colour error ^ (1 - df) — a changed edge or
// point raises the error towards 1.
#include "image.hpp"

namespace gt::quality {

// The FLIP error of every pixel. Both images must have the same size. The borders replicate
// the edge pixels.
[[nodiscard]] ScalarMap flipErrorMap(const RgbaImage& reference, const RgbaImage& test,
                                     double pixelsPerDegree);

// Pixels per degree of a viewer `distance` display widths from a display `widthPx` pixels wide,
// at the display's centre: N v pi / 180 (twice the display Nyquist of the thesis, eq. 3).
[[nodiscard]] double pixelsPerDegree(double widthPx, double viewingDistance);

} // namespace gt::quality
