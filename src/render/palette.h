// The renderer's colours and screen-space sizes for everything that is not the mesh surface (the surface's
// material and colour maps are in shaders/mesh.frag). The README's colour legend describes these.
// Colours are sRGB + alpha in [0, 1]; sizes are pixels at pixel scale 1 (a 1280 x 800 screenshot).
#pragma once

namespace sculpt::render {

struct Rgba {
    float r, g, b, a;
};

// Lattice control points: orange discs; selected ones yellow and larger; pinned ones dark grey squares
// with a light outline (yellow squares when also selected).
inline constexpr Rgba kControlPointColor = {1.00f, 0.55f, 0.10f, 1.0f};
inline constexpr Rgba kSelectedPointColor = {1.00f, 0.90f, 0.15f, 1.0f};
inline constexpr Rgba kPinnedPointColor = {0.20f, 0.20f, 0.22f, 1.0f};
inline constexpr float kControlPointSize = 8.0f;
inline constexpr float kSelectedPointSize = 11.0f;
inline constexpr float kPinnedPointSize = 9.0f;

// Lattice edges: thin and translucent, coloured by their end points (yellow toward selected points).
inline constexpr Rgba kLatticeEdgeColor = {1.00f, 0.66f, 0.32f, 0.42f};
inline constexpr Rgba kSelectedEdgeColor = {1.00f, 0.92f, 0.35f, 0.70f};
inline constexpr Rgba kPinnedEdgeColor = {0.62f, 0.62f, 0.66f, 0.42f};
inline constexpr float kLatticeEdgeWidth = 1.0f;
// Parts of the lattice hidden behind the mesh are still drawn, this much fainter, so the user sees the
// whole control volume without it competing with the surface.
inline constexpr float kOccludedAlpha = 0.3f;

// Constraints (Hu et al. 2001, Fig. 1): source S red, target T blue, a red-to-blue line between them over a
// dark underlay, always on top.
inline constexpr Rgba kSourceColor = {0.92f, 0.16f, 0.12f, 1.0f};
inline constexpr Rgba kTargetColor = {0.18f, 0.46f, 1.00f, 1.0f};
inline constexpr Rgba kHandleShadow = {0.04f, 0.04f, 0.05f, 0.55f};
inline constexpr float kHandleSize = 11.0f;
inline constexpr Rgba kSurfacePinColor = {0.20f, 0.78f, 0.38f, 1.0f};  // pinned surface points (squares)
inline constexpr float kHandleLineWidth = 2.5f;
inline constexpr float kHandleShadowWidth = 5.0f;

// World axes of transform guides (X, Y, Z), Blender's theme colours.
inline constexpr Rgba kAxisColors[3] = {{1.00f, 0.20f, 0.32f, 1.0f}, {0.55f, 0.86f, 0.00f, 1.0f}, {0.16f, 0.56f, 1.00f, 1.0f}};

// Wireframe overlay: dark translucent edges.
inline constexpr Rgba kWireColor = {0.10f, 0.10f, 0.12f, 0.40f};

}  // namespace sculpt::render
