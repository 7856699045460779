// The det J overlay's legend: a colour bar with its numbers and the fold-over swatch, drawn by the renderer
// itself (flat triangles, tiny bitmap digits) whenever the overlay is on, so the window and the headless
// screenshots both carry it.
#pragma once

#include <string>
#include <vector>

namespace sculpt::render {

inline constexpr int kOverlayFloats = 8;  // per vertex: window pixel xy, colour rgba, fill kind, map position

// Fill kinds of an overlay vertex (shaders/overlay2d.frag).
inline constexpr float kFillColor = 0.0f;        // the vertex colour
inline constexpr float kFillJacobianMap = 1.0f;  // the det J colour map at the map position (-1 .. 1)
inline constexpr float kFillFold = 2.0f;         // the fold-over stripes

// The legend's triangles (kOverlayFloats per vertex, three vertices per triangle, in drawing order) for a
// width x height view: a translucent panel in the bottom-right corner, `insetBottom` pixels above the
// bottom edge (a status line drawn over the view), with "det J (log scale)", the bar from 1 / range to
// range and its three numbers, and the fold-over swatch. Its pixel size grows with pixelScale (font pixels
// of max(1, round(2 * pixelScale)) window pixels). range > 1. Empty when the view is too small to hold it.
std::vector<float> buildJacobianLegend(int width, int height, float pixelScale, float insetBottom, float range);

// The pixels the legend takes above `insetBottom`, its margin included: a panel drawn over the view's bottom-right
// corner ends this far above the status line to leave it in sight.
float jacobianLegendHeight(float pixelScale);

// Text of a map end: "2", "1/2", "1.5", "1/1.5" (three significant digits).
std::string legendNumber(float value, bool reciprocal);

}  // namespace sculpt::render
