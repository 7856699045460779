// Vertical gradient between two sRGB colours (interpolated in sRGB, like a designer's gradient).
uniform vec3 uTopColor;
uniform vec3 uBottomColor;

in float vDown;
out vec4 fragColor;

void main() {
    fragColor = vec4(mix(uTopColor, uBottomColor, clamp(vDown, 0.0, 1.0)), 1.0);
}
