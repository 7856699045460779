// Orbit camera: looks at `target` from `distance` along the direction given by yaw and pitch.
// GLM lives in render and app only (never in core).
#pragma once

#include <glm/glm.hpp>

#include "core/mesh_types.h"

namespace sculpt::render {

// Axis-aligned box, plus (when known) the radius of the tightest sphere about the box centre that holds
// the points: framing with it instead of the box's half diagonal makes a round object fill the view.
struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
    bool empty = true;           // no point added yet
    float sphereRadius = -1.0f;  // < 0: unknown (radius() falls back to the half diagonal)

    void add(const glm::vec3& point);  // makes sphereRadius unknown
    void add(const Bounds& other);     // keeps a conservative sphereRadius when both are known
    glm::vec3 center() const { return 0.5f * (min + max); }
    float radius() const;              // of a sphere about center() holding everything added
};

// Bounds of the rows of a #N x 3 array, with sphereRadius (empty bounds for N = 0; non-finite rows skipped).
Bounds boundsOf(const Positions& points);

struct Camera {
    float yawDeg = 30.0f;     // rotation about +Y; 0 looks along -Z (eye on +Z), positive turns the eye toward +X
    float pitchDeg = 20.0f;   // elevation of the eye above the target's horizontal plane, clamped to +-89
    float distance = 3.0f;    // eye to target, world units, > 0
    glm::vec3 target{0.0f};   // orbit centre
    float fovYDeg = 35.0f;    // vertical field of view
    float sceneRadius = 1.0f; // radius of the content, sets the near/far planes around the target

    // Points the camera at the box's centre and sets distance so that the bounding sphere (radius()) spans
    // `fill` (fraction; 0.8 leaves a margin) of the smaller of the vertical and horizontal field of view at
    // this aspect ratio (width / height). Keeps yaw, pitch and fov. Empty bounds leave the camera unchanged.
    void frame(const Bounds& bounds, float aspect, float fill = 0.8f);

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;
};

}  // namespace sculpt::render
