// Marker: a disc, square or diamond with an outline (1.5 pixels, thinner on small markers) that contrasts with its fill (dark around light fills,
// light around dark ones), antialiased over one pixel.
uniform float uAlphaScale;  // multiplies alpha (fainter pass for occluded markers)

in vec4 vColor;
in vec2 vPixels;
flat in float vRadius;
flat in float vShape;
out vec4 fragColor;

void main() {
    // shape 0: disc, 1: square, 2: diamond (a T-junction)
    float dist = vShape > 1.5 ? abs(vPixels.x) + abs(vPixels.y) : vShape > 0.5 ? max(abs(vPixels.x), abs(vPixels.y)) : length(vPixels);
    float coverage = clamp(vRadius - dist + 0.5, 0.0, 1.0);
    if (coverage <= 0.0) discard;
    float luminance = dot(vColor.rgb, vec3(0.2126, 0.7152, 0.0722));
    vec3 outline = luminance < 0.25 ? vec3(0.88, 0.88, 0.90) : vec3(0.06, 0.06, 0.07);
    float outlineWidth = clamp(0.3 * vRadius, 0.6, 1.5);
    float inside = clamp(vRadius - outlineWidth - dist + 0.5, 0.0, 1.0);
    fragColor = vec4(mix(outline, vColor.rgb, inside), vColor.a * coverage * uAlphaScale);
}
