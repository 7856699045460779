// Flat screen-space overlays: a plain colour, the det J colour map at an interpolated map position (the
// legend's bar, exactly the surface's colours), or the fold-over stripes.
#include "jacobian_colors.glsl"

in vec4 vColor;
flat in float vFillKind;
in float vMapPosition;
out vec4 fragColor;

void main() {
    if (vFillKind > 1.5) fragColor = vec4(foldColor(gl_FragCoord.xy), vColor.a);
    else if (vFillKind > 0.5) fragColor = vec4(jacobianMapColor(clamp(vMapPosition, -1.0, 1.0)), vColor.a);
    else fragColor = vColor;
}
