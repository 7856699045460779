// Screen-space line segments of constant pixel width: each instance is one segment, expanded to a quad
// (triangle strip of 4 vertices) around the projected segment. Core profile has no wide lines.
#include "depth_fade.glsl"

layout(location = ATTRIB_SEGMENT_START) in vec3 aStart;
layout(location = ATTRIB_SEGMENT_END) in vec3 aEnd;
layout(location = ATTRIB_COLOR_START) in vec4 aColorStart;
layout(location = ATTRIB_COLOR_END) in vec4 aColorEnd;

uniform mat4 uViewProjection;
uniform vec2 uViewport;   // pixels
uniform float uWidth;     // pixels, without the antialiasing fringe
// Depth cue: alpha is multiplied by 1 at device depth uDepthFade.x, by uDepthFade.z at uDepthFade.y and
// beyond (linear between); z = 1 turns it off.
uniform vec3 uDepthFade;

out vec4 vColor;
out float vAcross;        // signed distance from the centre line, pixels
flat out float vHalfWidth;

// Moves a clip-space point that lies behind the eye onto the near side along the segment, so that
// segments crossing the eye plane still draw their visible part.
vec4 clipToFront(vec4 point, vec4 other) {
    // note: w is a view depth in the renderer's local frame, where the scene's radius is 1 (camera.h), so
    // this is 1e-4 of the scene's size whatever the world units.
    const float minW = 1e-4;
    if (point.w >= minW) return point;
    float t = (minW - point.w) / (other.w - point.w);
    return mix(point, other, t);
}

void main() {
    vec4 start = uViewProjection * vec4(aStart, 1.0);
    vec4 end = uViewProjection * vec4(aEnd, 1.0);
    vec4 startClipped = clipToFront(start, end);
    vec4 endClipped = clipToFront(end, start);
    vec2 startPixels = startClipped.xy / startClipped.w * 0.5 * uViewport;
    vec2 endPixels = endClipped.xy / endClipped.w * 0.5 * uViewport;
    vec2 along = endPixels - startPixels;
    along = dot(along, along) > 1e-8 ? normalize(along) : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);

    bool atEnd = gl_VertexID >= 2;
    float side = (gl_VertexID & 1) == 0 ? -1.0 : 1.0;
    vHalfWidth = 0.5 * uWidth + 0.5;  // + half a pixel of fringe for antialiasing
    vec2 offsetPixels = across * side * vHalfWidth + along * (atEnd ? 1.0 : -1.0) * 0.5 * uWidth;
    vec4 clip = atEnd ? endClipped : startClipped;
    clip.xy += offsetPixels / (0.5 * uViewport) * clip.w;
    gl_Position = clip;
    vColor = atEnd ? aColorEnd : aColorStart;
    vColor.a *= depthFade(clip.z / clip.w, uDepthFade);
    vAcross = side * vHalfWidth;
}
