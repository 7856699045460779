// Antialiased screen-space line: full coverage inside the width, a one-pixel linear fringe outside.
uniform vec4 uTint;        // a > 0: replaces the per-vertex colour (rgb) and scales alpha by uTint.a
uniform float uAlphaScale; // multiplies alpha (fainter pass for occluded parts)

in vec4 vColor;
in float vAcross;
flat in float vHalfWidth;
out vec4 fragColor;

void main() {
    float coverage = clamp(vHalfWidth - abs(vAcross) + 0.5, 0.0, 1.0);
    vec4 color = uTint.a > 0.0 ? vec4(uTint.rgb, vColor.a * uTint.a) : vColor;
    fragColor = vec4(color.rgb, color.a * coverage * uAlphaScale);
}
