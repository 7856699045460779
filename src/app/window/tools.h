// The window's two editing tools and their state (view state only: the shape itself lives in the Session).
//
// Sculpt tool (multi-point direct manipulation, Hu et al. 2001 eq. 12, seed 000 Fig. 3-4): besides grabbing
// any surface point, the user can place handles (Shift+click) and pins (Ctrl+click) on the surface. Handles
// and pins are attached to the surface (a triangle and barycentric weights), so they ride along with every
// deformation, undo and redo. Every drag is one multi-point manipulation whose constraints are the grabbed
// point or handle(s) that move, plus every other handle and pin held where it is (target = source).
//
// Lattice tool: control points are picked (click, Shift+click toggles, drag a rectangle to box-select), dragged
// directly (Session::stroke().beginControl, one undo step per drag), and pinned or unpinned (P).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/deform/brush.h"
#include "core/volume/lattice.h"
#include "core/mesh_types.h"
#include "render/camera.h"

namespace sculpt::app {

enum class ToolMode { Sculpt, Lattice };

// A point attached to the mesh surface: the barycentric mix of a triangle's current corners.
struct SurfaceHandle {
    int triangle = 0;
    Eigen::Vector3d barycentric = Eigen::Vector3d(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
    bool pin = false;  // false: a handle that moves when dragged; true: held where it is
};

struct LatticeSelection {
    std::vector<int> points;  // sorted control point ids (Lattice::index) of the current lattice
    bool boxActive = false;   // a rectangle selection is being dragged
    bool boxAdditive = false; // Shift held when it began: add to the selection instead of replacing it
    double boxX0 = 0.0, boxY0 = 0.0, boxX1 = 0.0, boxY1 = 0.0;  // framebuffer pixels
    // The control point a click would pick where the cursor is (-1: none), ringed before the click, and where
    // it is drawn (world).
    int hovered = -1;
    Eigen::Vector3d hoveredAt = Eigen::Vector3d::Zero();
};

// The sculpt tool's brush (core/deform/brush.h), as in Blender's sculpt mode: a radius on screen (framebuffer pixels,
// turned into world units at the grabbed point when a drag begins), a strength, a falloff and X/Y/Z symmetry.
struct BrushTool {
    bool limited = true;           // false: a drag moves the whole cage (no radius)
    double radiusPixels = 70.0;    // in [kMinBrushPixels, kMaxBrushPixels]
    core::BrushSettings settings;  // strength, falloff, symmetry; the radius is set per drag
    // F (radius) or Shift+F (strength), then the mouse, as in Blender: the value follows the cursor's distance
    // from (centreX, centreY); a click or Enter keeps it, Esc or a right click puts `oldValue` back.
    enum class Resize { None, Radius, Strength } resize = Resize::None;
    double centreX = 0.0, centreY = 0.0, oldValue = 0.0;
    // The circle under the cursor: the surface point, its normal and the radius there in world units.
    bool hover = false;
    Eigen::Vector3d hoverPoint = Eigen::Vector3d::Zero(), hoverNormal = Eigen::Vector3d::UnitZ();
    double hoverRadius = 0.0;
    // Sculpting by weights on a frozen weighted T-spline (Session::tspline().sculptWeights, Song & Yang 2005 sec. 1 and 6):
    // what a click on the mesh does instead of a drag. The hammer raises the clicked vertex by hammerStep of the
    // mesh diagonal (Ctrl+click lowers it); the crimp multiplies the bump's width at half height by crimpFactor
    // (Ctrl+click divides). Both act on the visible control points within the brush radius (the strongest one
    // alone when the radius is off).
    enum class Kind { Drag, Hammer, Crimp } kind = Kind::Drag;
    double hammerStep = 0.01;   // in [0.001, 0.05]
    double crimpFactor = 1.25;  // in [1.02, 2]
};
constexpr double kMinBrushPixels = 5.0, kMaxBrushPixels = 1000.0;
constexpr double kStrengthPixels = 200.0;  // Shift+F: the cursor this far from the centre is strength 1

struct ToolState {
    BrushTool brush;
    ToolMode mode = ToolMode::Sculpt;
    std::vector<SurfaceHandle> handles;
    bool moveHandlesTogether = true;  // dragging one handle moves every (non-pin) handle by the same offset
    LatticeSelection lattice;
    std::string hint;  // what the cursor would do here, shown at the right of the status line
    core::LatticeSettings setup;  // the lattice set-up panel's fields
    bool setupEdited = false;     // false: the fields follow the session's current settings
};

// How many of the placed markers are pins.
size_t pinCount(const ToolState& tools);

// World position of a surface handle on the current mesh (positions #V x 3, triangles #F x 3).
Eigen::Vector3d handlePosition(const SurfaceHandle& handle, const Positions& positions, const Triangles& triangles);

// Pixel position of a world point in a width x height view; false if it is behind the eye or the view is empty.
bool projectToPixel(const render::Camera& camera, int width, int height, const Eigen::Vector3d& point,
                    double& x, double& y);

// Index of the handle whose marker is nearest to pixel (x, y) within `radius` pixels, or -1.
int handleAtPixel(const ToolState& tools, const Positions& positions, const Triangles& triangles,
                  const render::Camera& camera, int width, int height, double x, double y, double radius);

// The control point (id) a click at pixel (x, y) picks, or -1: of the markers within `radius` pixels, those that
// overlap the nearest on screen (within `overlap` pixels of its distance: one target to the user) are under the
// cursor; among them a free point wins over a pinned one (pinned: empty, none pinned, or #P flags), then the one
// nearest the eye. So on a lattice of any shape a click on a visible free point never picks the pinned outer one
// drawn over or behind it. controlPoints #P x 3; shown: empty (all), or #P flags, and only points flagged nonzero
// (those the lattice overlay draws) count. radius, overlap >= 0.
int controlPointAtPixel(const Positions& controlPoints, const std::vector<std::uint8_t>& shown,
                        const render::Camera& camera, int width, int height, double x, double y, double radius,
                        const std::vector<std::uint8_t>& pinned = {}, double overlap = 1.0);

// Control points (of those `shown`, as above) whose projection lies inside the pixel rectangle (any two
// opposite corners), sorted.
std::vector<int> controlPointsInRectangle(const Positions& controlPoints, const std::vector<std::uint8_t>& shown,
                                          const render::Camera& camera, int width, int height, double x0, double y0,
                                          double x1, double y1);

// Sorted-set helpers for the selection.
void toggleInSelection(std::vector<int>& selection, int id);
void addToSelection(std::vector<int>& selection, const std::vector<int>& ids);

}  // namespace sculpt::app
