// The sculpt tool's brush (tools.h BrushTool, core/deform/brush.h), with Blender's keys: F and a mouse move sets
// the radius, Shift+F the strength; a click or Enter keeps the value, Esc or a right click cancels. The
// circle is drawn on the surface under the cursor, at the radius a drag grabbing there would get.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/window/picking.h"
#include "app/window/sculpt_app.h"

namespace sculpt::app {
namespace {

Eigen::Vector3d towardsEye(const render::Camera& camera) {
    const glm::dvec3 d = camera.towardEye();
    return Eigen::Vector3d(d.x, d.y, d.z);
}

// World length of `pixels` framebuffer pixels at `point`, in the plane through it facing the camera; 0 where
// the point does not project (behind the eye, empty view).
double worldLengthAt(const render::Camera& camera, int width, int height, const Eigen::Vector3d& point, double pixels) {
    double x = 0.0, y = 0.0;
    if (!projectToPixel(camera, width, height, point, x, y)) return 0.0;
    Ray ray;
    Eigen::Vector3d hit;
    if (!rayThroughPixel(camera, width, height, x + pixels, y, ray) || !intersectPlane(ray, point, towardsEye(camera), hit)) return 0.0;
    return (hit - point).norm();
}

std::string brushDescription(const BrushTool& brush) {
    char text[160];
    std::snprintf(text, sizeof text, "Brush: radius %.0f px, strength %.2f, %s falloff%s%s.", brush.radiusPixels, brush.settings.strength,
                  core::brushFalloffName(brush.settings.falloff), brush.settings.symmetry.any() ? ", symmetric in " : "",
                  core::symmetryText(brush.settings.symmetry, true).c_str());
    return text;
}

// Ends an F / Shift+F resize: keep the new value, or put the old one back.
void finishBrushResize(AppState& state, bool keep) {
    BrushTool& brush = state.tools.brush;
    if (!keep) (brush.resize == BrushTool::Resize::Radius ? brush.radiusPixels : brush.settings.strength) = brush.oldValue;
    setStatus(state, (keep ? "" : "Brush unchanged. ") + brushDescription(brush), false);
    brush.resize = BrushTool::Resize::None;
    state.gpu.fields = true;
}

}  // namespace

core::BrushSettings SculptApp::brushForDrag(const Eigen::Vector3d& at) const {
    const BrushTool& brush = state_.tools.brush;
    core::BrushSettings settings = brush.settings;
    settings.radius = brush.limited ? worldLengthAt(state_.camera, state_.framebufferWidth, state_.framebufferHeight, at, brush.radiusPixels) : 0.0;
    if (!std::isfinite(settings.radius)) settings.radius = 0.0;
    return settings;
}

bool SculptApp::brushKey(const KeyEvent& event) {
    BrushTool& brush = state_.tools.brush;
    if (event.action != KeyAction::Press) return false;
    if (brush.resize != BrushTool::Resize::None) {
        if (event.key == Key::Enter || event.key == Key::Escape) {
            finishBrushResize(state_, event.key == Key::Enter);
            updateBrushHover(state_.cursorX, state_.cursorY);  // the circle comes back under the cursor, at its size
        }
        return true;  // nothing else acts while the brush is being resized
    }
    if (event.key != Key::F || state_.tools.mode != ToolMode::Sculpt || state_.drag.active || event.modifiers.control ||
        event.modifiers.super || event.modifiers.alt)
        return false;
    // As in Blender: the circle's centre sits one radius (or the strength's length) left of the cursor, so
    // the value starts where it was and follows the cursor's distance from there.
    const bool strength = event.modifiers.shift;
    brush.resize = strength ? BrushTool::Resize::Strength : BrushTool::Resize::Radius;
    brush.oldValue = strength ? brush.settings.strength : brush.radiusPixels;
    const double length = strength ? brush.settings.strength * kStrengthPixels : brush.radiusPixels;
    brush.centreX = state_.cursorX - length;
    brush.centreY = state_.cursorY;
    // The circle is drawn round that centre, facing the eye (as Blender draws it while resizing), so the
    // cursor sits on its rim as the radius follows it: a new user found it drawn round the cursor while the
    // radius was measured from a point one radius left, and then, lying on the tilted surface, short of it.
    Eigen::Vector3d centre, normal;
    // Off the mesh (the centre one radius left of the cursor can be beside it), the circle is drawn at the
    // depth of the orbit centre: a trial saw no circle at all while resizing there.
    Ray centreRay;
    bool placed = !strength && surfaceUnderPixel(brush.centreX, brush.centreY, centre, normal);
    if (!strength && !placed && !state_.session.mesh().empty() &&
        rayThroughPixel(state_.camera, state_.framebufferWidth, state_.framebufferHeight, brush.centreX, brush.centreY, centreRay)) {
        const Eigen::Vector3d target(state_.camera.target.x, state_.camera.target.y, state_.camera.target.z);
        const double along = (target - centreRay.origin).dot(centreRay.direction) / centreRay.direction.squaredNorm();
        centre = centreRay.origin + std::max(along, 0.0) * centreRay.direction;
        placed = centre.allFinite();
    }
    if (placed) {
        const glm::dvec3 eye = state_.camera.towardEye();
        brush.hover = true;
        brush.hoverPoint = centre;
        brush.hoverNormal = Eigen::Vector3d(eye.x, eye.y, eye.z).normalized();
        brush.hoverRadius = brushForDrag(centre).radius;
        state_.gpu.fields = true;
    }
    brush.limited = brush.limited || !strength;
    setStatus(state_, strength ? "Move the mouse to set the brush strength; click or Enter keeps it, Esc cancels."
                               : "Move the mouse to set the brush radius; click or Enter keeps it, Esc cancels.",
              false);
    return true;
}

bool SculptApp::brushMouseMove(double x, double y) {
    BrushTool& brush = state_.tools.brush;
    if (brush.resize == BrushTool::Resize::None) return false;
    const double length = std::hypot(x - brush.centreX, y - brush.centreY);
    if (brush.resize == BrushTool::Resize::Radius) brush.radiusPixels = std::clamp(length, kMinBrushPixels, kMaxBrushPixels);
    else brush.settings.strength = std::clamp(length / kStrengthPixels, 0.01, 1.0);
    char text[96];
    if (brush.resize == BrushTool::Resize::Radius) std::snprintf(text, sizeof text, "Brush radius: %.0f px", brush.radiusPixels);
    else std::snprintf(text, sizeof text, "Brush strength: %.2f", brush.settings.strength);
    setStatus(state_, text, false);
    state_.gpu.fields = true;
    if (brush.hover) brush.hoverRadius = brushForDrag(brush.hoverPoint).radius;  // the circle grows and shrinks live
    return true;
}

bool SculptApp::brushMouseButton(const MouseButtonEvent& event) {
    BrushTool& brush = state_.tools.brush;
    if (brush.resize == BrushTool::Resize::None || event.action != ButtonAction::Press) return false;
    finishBrushResize(state_, event.button != MouseButton::Right);
    updateBrushHover(state_.cursorX, state_.cursorY);  // the circle comes back under the cursor, at its size
    return true;
}

bool SculptApp::surfaceUnderPixel(double x, double y, Eigen::Vector3d& point, Eigen::Vector3d& normal) const {
    const core::Session& session = state_.session;
    Ray ray;
    if (session.mesh().empty() || !rayThroughPixel(state_.camera, state_.framebufferWidth, state_.framebufferHeight, x, y, ray)) return false;
    const SurfaceHit hit = intersectMesh(ray, session.mesh().positions, session.mesh().triangles);
    if (hit.triangle < 0) return false;
    const Eigen::Vector3d a = session.mesh().positions.row(session.mesh().triangles(hit.triangle, 0)).transpose();
    const Eigen::Vector3d b = session.mesh().positions.row(session.mesh().triangles(hit.triangle, 1)).transpose();
    const Eigen::Vector3d c = session.mesh().positions.row(session.mesh().triangles(hit.triangle, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0.0)) return false;
    point = hit.point;
    normal = n.normalized();
    return true;
}

void SculptApp::updateBrushHover(double x, double y) {
    BrushTool& brush = state_.tools.brush;
    const core::Session& session = state_.session;
    const bool wasShown = brush.hover;
    brush.hover = false;
    if (state_.tools.mode == ToolMode::Sculpt && !session.mesh().empty() && brush.limited && state_.navigation == Navigation::None) {
        // While resizing, the circle stays where it was: only its size follows the cursor.
        if (brush.resize != BrushTool::Resize::None) {
            brush.hover = wasShown;
        } else {
            Eigen::Vector3d point, normal;
            brush.hover = surfaceUnderPixel(x, y, point, normal);
            if (brush.hover) {
                brush.hoverPoint = point;
                brush.hoverNormal = normal;
            }
        }
        if (brush.hover) brush.hoverRadius = brushForDrag(brush.hoverPoint).radius;
    }
    if (brush.hover || wasShown) state_.gpu.fields = true;
}

}  // namespace sculpt::app
