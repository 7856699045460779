// Screen-space markers (control points, constraint handles): each instance is a quad of a fixed pixel
// size centred on a 3D point, depth-tested at the centre's depth.
#include "depth_fade.glsl"

layout(location = ATTRIB_MARKER_CENTER) in vec3 aCenter;
layout(location = ATTRIB_MARKER_COLOR) in vec4 aColor;
// (diameter in pixels, shape: 0 disc 1 square 2 diamond, depth fade: 0 none 1 by uDepthFade as the lattice edges;
// 1 and 2 shrink by uCrowdScale, 2 without the fade)
layout(location = ATTRIB_MARKER_STYLE) in vec3 aStyle;

uniform mat4 uViewProjection;
uniform vec2 uViewport;     // pixels
uniform float uSizeScale;   // multiplies every diameter (HiDPI, pass emphasis)
uniform float uCrowdScale;  // multiplies the depth-faded (unselected) markers' diameters where they crowd
uniform vec3 uDepthFade;    // as in line.vert

out vec4 vColor;
out vec2 vPixels;           // offset from the centre, pixels
flat out float vRadius;
flat out float vShape;

void main() {
    vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, gl_VertexID >= 2 ? 1.0 : -1.0);
    vRadius = 0.5 * aStyle.x * uSizeScale * (aStyle.z > 0.5 ? uCrowdScale : 1.0);
    float extent = vRadius + 1.0;  // one pixel of fringe for antialiasing
    vec4 clip = uViewProjection * vec4(aCenter, 1.0);
    vPixels = corner * extent;
    clip.xy += vPixels / (0.5 * uViewport) * clip.w;
    // Behind the eye: put the vertex outside the clip volume so nothing is drawn.
    if (clip.w <= 0.0) clip = vec4(2.0, 2.0, 2.0, 1.0);
    gl_Position = clip;
    vColor = aColor;
    if (aStyle.z > 0.5 && aStyle.z < 1.5) vColor.a *= depthFade(clip.z / clip.w, uDepthFade);
    vShape = aStyle.y;
}
