// Orbit camera: looks at `target` from `distance` along the direction given by yaw and pitch.
// GLM lives in render and app only (never in core).
//
// Any scale, any place: everything in world units is double and relative to the content. Framing, the
// near/far planes, zoom limits and the local frame below follow the content's radius (a 1e-9 or a 1e9 mesh
// frames alike), and the GPU never sees world coordinates: the renderer draws in a LocalFrame, world minus a
// scene origin, divided by the scene's radius, computed in double before anything becomes float (the usual
// camera-relative rendering), so a 1e-3 mesh centred at 1e7 keeps float's seven digits for its own shape.
#pragma once

#include <glm/glm.hpp>

#include "core/mesh_types.h"

namespace sculpt::render {

// Axis-aligned box, plus (when known) the radius of the tightest sphere about the box centre that holds
// the points: framing with it instead of the box's half diagonal makes a round object fill the view.
struct Bounds {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    bool empty = true;            // no point added yet
    double sphereRadius = -1.0;   // < 0: unknown (radius() falls back to the half diagonal)

    void add(const glm::dvec3& point);  // makes sphereRadius unknown
    void add(const Bounds& other);      // keeps a conservative sphereRadius when both are known
    glm::dvec3 center() const { return 0.5 * (min + max); }
    double radius() const;              // of a sphere about center() holding everything added
};

// Bounds of the rows of a #N x 3 array, with sphereRadius (empty bounds for N = 0; non-finite rows skipped).
Bounds boundsOf(const Positions& points);

// The radius framing uses for these bounds: radius(), or where that is 0 (a single point) 1e-3 of the
// point's distance from the origin, or 1 for a point at the origin; 1 for empty bounds. Always > 0 and finite
// for finite bounds.
double framingRadius(const Bounds& bounds);

// Where the GPU works: local = (world - origin) / scale, scale > 0. Chosen by the renderer from the content
// (origin at its centre, scale its framing radius), so local coordinates, view depths and clip w are near 1
// whatever the units, and a position far from the world origin loses no digits to float.
struct LocalFrame {
    glm::dvec3 origin{0.0};
    double scale = 1.0;

    glm::dvec3 toLocal(const glm::dvec3& world) const { return (world - origin) / scale; }
    glm::dvec3 toWorld(const glm::dvec3& local) const { return origin + scale * local; }
    bool operator==(const LocalFrame& other) const { return origin == other.origin && scale == other.scale; }
    bool operator!=(const LocalFrame& other) const { return !(*this == other); }
};

// The local frame of content with these bounds: origin at center(), scale framingRadius() (the identity
// frame for empty bounds).
LocalFrame localFrameOf(const Bounds& bounds);

struct Camera {
    float yawDeg = 30.0f;       // rotation about +Y; 0 looks along -Z (eye on +Z), positive turns the eye toward +X
    float pitchDeg = 20.0f;     // elevation of the eye above the target's horizontal plane, clamped to +-90
                                // (+-90: straight down or up, the screen's up then -Z or +Z turned by yaw)
    double distance = 3.0;      // eye to target, world units, > 0
    glm::dvec3 target{0.0};     // orbit centre, world units
    float fovYDeg = 35.0f;      // vertical field of view
    // Parallel projection: the view shows 2 * distance * tan(fovY / 2) world units vertically, what the
    // perspective view shows at the target's depth, so switching keeps the target's size and zoom still
    // works by changing distance.
    bool orthographic = false;
    double sceneRadius = 1.0;   // radius of the content, world units: sets the near/far planes and zoom limits

    // Points the camera at the box's centre and sets distance so that the bounding sphere (framingRadius())
    // spans `fill` (fraction; 0.8 leaves a margin) of the smaller of the vertical and horizontal field of view
    // at this aspect ratio (width / height). Keeps yaw, pitch and fov. Empty bounds leave the camera unchanged.
    void frame(const Bounds& bounds, float aspect, float fill = 0.8f);

    glm::dvec3 eye() const;       // world position of the eye
    glm::dvec3 towardEye() const; // unit vector from the target to the eye
    // World-space unit vectors of the view: right and up on the screen (as glm::lookAt with +Y up).
    glm::dvec3 right() const;
    glm::dvec3 up() const;
    // World units per pixel at the target's depth (everywhere when orthographic), for a view `height` pixels
    // tall (pan, screen-space sizes).
    double worldPerPixel(int height) const;

    // View and projection in `frame`'s local coordinates (world by default), in double: the renderer converts
    // them to float after the frame took the scene's origin and scale out; picking projects in double.
    // Near and far hug the content (see projection's comment in camera.cpp).
    glm::dmat4 view(const LocalFrame& frame = {}) const;
    glm::dmat4 projection(double aspect, const LocalFrame& frame = {}) const;
};

}  // namespace sculpt::render
