#include "app/window/view_navigation.h"

#include <algorithm>
#include <cmath>

#include "app/window/picking.h"
#include "app/window/tool_commands.h"

namespace sculpt::app {
namespace {

constexpr double kOrbitDegreesPerPixel = 0.35;
constexpr double kZoomPerNotch = 0.88;  // distance factor per wheel notch towards the screen

}  // namespace

void setAxisView(AppState& state, AxisView view, bool opposite) {
    render::Camera& camera = state.camera;
    switch (view) {
        case AxisView::Front: camera.yawDeg = opposite ? 180.0f : 0.0f; camera.pitchDeg = 0.0f; break;
        case AxisView::Right: camera.yawDeg = opposite ? -90.0f : 90.0f; camera.pitchDeg = 0.0f; break;
        case AxisView::Top: camera.yawDeg = 0.0f; camera.pitchDeg = opposite ? -90.0f : 90.0f; break;
    }
    if (!camera.orthographic) {
        camera.orthographic = true;
        state.orthographicByAxisView = true;
    }
    static const char* const kNames[3][2] = {{"Front", "Back"}, {"Right", "Left"}, {"Top", "Bottom"}};
    setStatus(state, std::string(kNames[static_cast<int>(view)][opposite ? 1 : 0]) + " view (" +
                         (camera.orthographic ? "orthographic" : "perspective") + "; numpad 5 toggles).",
              false);
}

void toggleOrthographic(AppState& state) {
    state.camera.orthographic = !state.camera.orthographic;
    state.orthographicByAxisView = false;
    setStatus(state, state.camera.orthographic ? "Orthographic view (numpad 5: perspective)."
                                               : "Perspective view (numpad 5: orthographic).",
              false);
}

void orbitView(AppState& state, double dx, double dy) {
    render::Camera& camera = state.camera;
    camera.yawDeg = static_cast<float>(std::remainder(camera.yawDeg - dx * kOrbitDegreesPerPixel, 360.0));
    camera.pitchDeg = static_cast<float>(std::clamp(camera.pitchDeg + dy * kOrbitDegreesPerPixel, -90.0, 90.0));
    if (state.orthographicByAxisView && (dx != 0.0 || dy != 0.0)) {
        camera.orthographic = false;
        state.orthographicByAxisView = false;
    }
}

void panView(AppState& state, double dx, double dy) {
    if (state.framebufferHeight <= 0) return;
    render::Camera& camera = state.camera;
    // World units per pixel at the target's depth (double, so a pan by a pixel of a 1e-3 mesh at 1e7 is not
    // rounded away).
    const double worldPerPixel = camera.worldPerPixel(state.framebufferHeight);
    camera.target += (-dx * camera.right() + dy * camera.up()) * worldPerPixel;
}

void zoomView(AppState& state, double x, double y, double notches) {
    if (!std::isfinite(notches)) return;
    render::Camera& camera = state.camera;
    // Zoom is a factor, and its limits are relative to the content's radius: alike at every scale.
    const double minDistance = 1e-3 * camera.sceneRadius, maxDistance = 1e3 * camera.sceneRadius;
    const double wanted = camera.distance * std::pow(kZoomPerNotch, std::clamp(notches, -10.0, 10.0));
    const double distance = std::clamp(wanted, minDistance, maxDistance);
    const double factor = distance / camera.distance;
    // The point under the cursor on the plane through the target facing the eye keeps its pixel when the
    // target moves toward it by the same factor as the distance (both projections scale about the target).
    Ray ray;
    Eigen::Vector3d under;
    const glm::dvec3 toward = camera.towardEye();
    if (rayThroughPixel(camera, state.framebufferWidth, state.framebufferHeight, x, y, ray) &&
        intersectPlane(ray, Eigen::Vector3d(camera.target.x, camera.target.y, camera.target.z),
                       Eigen::Vector3d(toward.x, toward.y, toward.z), under)) {
        const glm::dvec3 point(under.x(), under.y(), under.z());
        camera.target = point + (camera.target - point) * factor;
    }
    camera.distance = distance;
}

void frameSelected(AppState& state) {
    clampLatticeSelection(state);
    const std::vector<int>& selection = state.tools.lattice.points;
    if (state.tools.mode != ToolMode::Lattice || selection.empty()) {
        frameMesh(state);
        return;
    }
    render::Bounds bounds;
    for (int id : selection) {
        const Eigen::Vector3d p = state.session.lattice().controlPoint(id);
        bounds.add(glm::dvec3(p.x(), p.y(), p.z()));
    }
    render::Camera& camera = state.camera;
    // A single point has no size: it fills the view as a twentieth of the content would. The content's radius
    // stays (it places the near and far planes around everything, not just the selection).
    bounds.sphereRadius = std::max(0.5 * glm::length(bounds.max - bounds.min), 0.05 * camera.sceneRadius);
    const double sceneRadius = camera.sceneRadius;
    camera.frame(bounds, framebufferAspect(state));
    camera.sceneRadius = sceneRadius;
    setStatus(state, "Framed the selected control points (Home or F: everything).", false);
}

}  // namespace sculpt::app
