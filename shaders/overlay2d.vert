// Flat screen-space overlays (the det J legend): triangles in window pixels, origin at the top-left corner.
layout(location = ATTRIB_OVERLAY_PIXEL) in vec2 aPixel;
layout(location = ATTRIB_OVERLAY_COLOR) in vec4 aColor;  // sRGB + alpha
layout(location = ATTRIB_OVERLAY_FILL) in vec2 aFill;    // (0 plain colour, 1 det J map, 2 fold stripes; map position)

uniform vec2 uViewport;  // pixels

out vec4 vColor;
flat out float vFillKind;
out float vMapPosition;

void main() {
    gl_Position = vec4(aPixel.x / uViewport.x * 2.0 - 1.0, 1.0 - aPixel.y / uViewport.y * 2.0, 0.0, 1.0);
    vColor = aColor;
    vFillKind = aFill.x;
    vMapPosition = aFill.y;
}
