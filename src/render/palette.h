// The renderer's colours and screen-space sizes for everything that is not the mesh surface (the surface's
// material and colour maps are in shaders/mesh.frag). docs/engine.md, "Colours in pictures", describes these.
// Colours are sRGB + alpha in [0, 1]; sizes are pixels at pixel scale 1 (a 1280 x 800 screenshot).
#pragma once

namespace sculpt::render {

struct Rgba {
    float r, g, b, a;
};

// Lattice control points, as in Blender's lattice edit mode: unselected ones small dark dots (they must not
// hide the mesh: a 16^3 lattice has 4,096), selected ones bright orange and larger, pinned ones light blue
// squares (orange squares when also selected).
inline constexpr Rgba kControlPointColor = {0.07f, 0.07f, 0.08f, 0.85f};
inline constexpr Rgba kSelectedPointColor = {1.00f, 0.55f, 0.08f, 1.0f};
inline constexpr Rgba kPinnedPointColor = {0.55f, 0.72f, 0.95f, 1.0f};
inline constexpr float kControlPointSize = 4.5f;
inline constexpr float kSelectedPointSize = 8.0f;
inline constexpr float kPinnedPointSize = 6.0f;
// Crowded markers (crowdedMarkerScale, overlay_geometry.h): where, on average, more than this share of the
// cells within two marker diameters of a marker hold another one, the unselected markers shrink (a small
// frozen lattice seen from afar, a fine grid), down to this factor (2 px dots; the selected ones keep their
// size). A square grid 2 diameters apart fills 1/3 of them; 3 apart, none.
inline constexpr float kCrowdedMarkerShare = 0.15f;
inline constexpr float kMinCrowdedMarkerScale = 0.45f;

// Lattice edges: one pixel, translucent mid grey (readable over the light clay and the dark background
// alike), orange toward selected points, blue toward pinned ones.
inline constexpr Rgba kLatticeEdgeColor = {0.58f, 0.60f, 0.64f, 0.55f};
inline constexpr Rgba kSelectedEdgeColor = {1.00f, 0.60f, 0.15f, 0.85f};
inline constexpr Rgba kPinnedEdgeColor = {0.55f, 0.70f, 0.92f, 0.55f};
inline constexpr float kLatticeEdgeWidth = 1.0f;
// A lattice of any shape: the curved chunk edges of its volume (what the surface follows), teal so they read
// apart from the straight grey control net; lattice tools that are not frozen, dim grey.
inline constexpr Rgba kLatticeCurveColor = {0.16f, 0.62f, 0.70f, 0.85f};
inline constexpr Rgba kLatticeToolColor = {0.50f, 0.52f, 0.58f, 0.45f};
// Weighted T-splines: T-junctions of the T-lattice as small yellow diamonds (a dark outline keeps them
// readable over the light clay), and the edges of cells chosen for subdivision in the selection's orange.
inline constexpr Rgba kTJunctionColor = {0.98f, 0.84f, 0.22f, 0.95f};
inline constexpr float kTJunctionSize = 8.0f;
inline constexpr Rgba kChosenCellColor = {1.00f, 0.55f, 0.08f, 0.95f};
// Depth cue: edges and unselected points fade from full strength at the lattice's nearest point to this
// at its farthest, so the front of the cage reads over the back.
inline constexpr float kLatticeFarAlpha = 0.3f;
// Parts of the lattice hidden behind the mesh are still drawn, this much fainter, so the user sees the
// whole control volume without it competing with the surface.
inline constexpr float kOccludedAlpha = 0.3f;

// Constraints (Hu et al. 2001, Fig. 1): source S red, target T blue, a red-to-blue line between them over a
// dark underlay, always on top.
inline constexpr Rgba kSourceColor = {0.92f, 0.16f, 0.12f, 1.0f};
inline constexpr Rgba kTargetColor = {0.18f, 0.46f, 1.00f, 1.0f};
inline constexpr Rgba kHandleShadow = {0.04f, 0.04f, 0.05f, 0.55f};
inline constexpr float kHandleSize = 11.0f;
inline constexpr Rgba kSurfacePinColor = {0.20f, 0.78f, 0.38f, 1.0f};
inline constexpr Rgba kBrushOutlineColor = {0.95f, 0.95f, 0.95f, 0.9f};  // the sculpt brush's circle  // pinned surface points (squares)
inline constexpr float kHandleLineWidth = 2.5f;
inline constexpr float kHandleShadowWidth = 5.0f;

// The det J legend (legend.h): light text on a translucent dark panel, like the window's panels. The map's
// own colours are in shaders/jacobian_colors.glsl; it saturates at 1 / kJacobianRange and kJacobianRange, so
// that a moderate edit (det J 0.8 .. 1.25) already shows 40% of the full colour.
inline constexpr float kJacobianRange = 2.0f;
inline constexpr Rgba kLegendPanelColor = {0.08f, 0.08f, 0.09f, 0.72f};
inline constexpr Rgba kLegendTextColor = {0.92f, 0.92f, 0.94f, 1.0f};
// World axes of transform guides (X, Y, Z), Blender's theme colours.
inline constexpr Rgba kAxisColors[3] = {{1.00f, 0.20f, 0.32f, 1.0f}, {0.55f, 0.86f, 0.00f, 1.0f}, {0.16f, 0.56f, 1.00f, 1.0f}};

// Wireframe overlay: dark translucent edges.
inline constexpr Rgba kWireColor = {0.10f, 0.10f, 0.12f, 0.40f};

}  // namespace sculpt::render
