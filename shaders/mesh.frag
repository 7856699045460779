// Mesh surface: a neutral clay material under a soft key + fill light with a slight rim, lit in linear
// RGB and written gamma-encoded (sRGB). Optional overlays recolour the albedo:
//  - det J colour map (jacobian_colors.glsl: diverging, log scale, saturating at 1/2 and 2 by default; fold-over
//    det J <= 0 is loud magenta/black)
//  - affected-region weight, tinting toward a green highlight.
// The material is the clay, or the mesh's own vertex colours (a scan's) where uShowVertexColors says so.
// uMode 1 draws the wireframe overlay with a flat colour instead.
uniform int uMode;            // 0 shaded surface, 1 wireframe lines
uniform vec4 uWireColor;      // sRGB + alpha, for uMode 1
uniform int uShowJacobian;    // nonzero: colour by det J
uniform int uShowAffected;    // nonzero: tint by affected weight
uniform int uShowVertexColors;  // nonzero: the vertex colours (sRGB) are the material

in vec3 vViewPosition;
in vec3 vViewNormal;
in float vJacobian;
in float vAffected;
in vec3 vVertexColor;
out vec4 fragColor;

#include "jacobian_colors.glsl"

// sRGB colours of the affected-region map (see "Colours in pictures" in docs/engine.md); the material is kClay.
const vec3 kHighlight = vec3(0.10, 0.85, 0.45);  // affected region: green
const vec3 kHighlightLine = vec3(0.02, 0.30, 0.14); // its boundary and half-weight iso-lines: dark green

vec3 toLinear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 toSrgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

// Coverage of an antialiased iso-line value == level, halfWidth pixels either side: the distance to the
// line in pixels is the value's difference over its screen-space gradient (a first-order estimate, exact for
// the linear interpolation across a triangle), faded out over one pixel.
float isoLine(float value, float level, float halfWidth) {
    float gradient = length(vec2(dFdx(value), dFdy(value)));  // value is a weight, not a length: no unit involved
    float pixels = abs(value - level) / max(gradient, 1e-6);
    return 1.0 - smoothstep(halfWidth - 0.5, halfWidth + 0.5, pixels);
}

// Wrapped diffuse: light reaches a little past the terminator, which reads as soft, large light sources.
float wrapDiffuse(vec3 n, vec3 l, float wrap) { return max((dot(n, l) + wrap) / (1.0 + wrap), 0.0); }

void main() {
    if (uMode == 1) {
        fragColor = uWireColor;
        return;
    }
    // Derivatives (fwidth) only in uniform control flow, before the fold-over branch below.
    float affectedLines = 0.0;
    if (uShowAffected != 0) {
        // Thin darker iso-lines at the edge of the region (weight 0.02) and at half influence (0.5), drawn on the
        // cube root of the weight: a B-spline influence fades like the cube of the distance to its support's
        // edge, so the weight itself is nearly flat there (a line on it would be wide and ragged) while its
        // cube root changes at an even rate across the region.
        float evenWeight = pow(clamp(vAffected, 0.0, 1.0), 1.0 / 3.0);
        affectedLines = max(isoLine(evenWeight, 0.2714, 0.8), 0.6 * isoLine(evenWeight, 0.7937, 0.8));
    }
    if (uShowJacobian != 0 && !(vJacobian > 0.0)) {
        // Fold-over (or NaN): unlit stripes, so it cannot be mistaken for shading or missed in a shadow.
        fragColor = vec4(foldColor(gl_FragCoord.xy), 1.0);
        return;
    }
    // note: the plain material's linear albedo is a constant the compiler folds; overlays pay for pow().
    vec3 material = uShowVertexColors != 0 ? clamp(vVertexColor, 0.0, 1.0) : kClay;
    vec3 albedo = uShowVertexColors != 0 ? toLinear(material) : toLinear(kClay);
    float highlight = 0.0;
    if (uShowJacobian != 0 || uShowAffected != 0) {
        vec3 albedoSrgb = uShowJacobian != 0 ? jacobianMapColor(jacobianMapPosition(vJacobian)) : material;
        if (uShowAffected != 0) {
            highlight = clamp(vAffected, 0.0, 1.0);
            albedoSrgb = mix(albedoSrgb, kHighlight, 0.75 * highlight);
            albedoSrgb = mix(albedoSrgb, kHighlightLine, 0.8 * affectedLines);
        }
        albedo = toLinear(albedoSrgb);
    }

    vec3 n = normalize(vViewNormal);
    if (!gl_FrontFacing) n = -n;  // open meshes: light the inside as well, see below
    vec3 v = normalize(-vViewPosition);

    // Lights are fixed to the camera (view space), so any view of the mesh is well lit.
    const vec3 keyDirection = normalize(vec3(-0.65, 0.55, 0.45));   // upper left, in front
    const vec3 fillDirection = normalize(vec3(0.60, -0.20, 0.75));  // right, low, frontal
    const vec3 rimDirection = normalize(vec3(0.25, 0.55, -0.80));   // behind, above
    const vec3 keyColor = vec3(1.00, 0.96, 0.90) * 1.0;
    const vec3 fillColor = vec3(0.80, 0.88, 1.00) * 0.18;
    const vec3 skyColor = vec3(0.065, 0.07, 0.08);
    const vec3 groundColor = vec3(0.02, 0.018, 0.016);

    float key = wrapDiffuse(n, keyDirection, 0.05);
    float fill = wrapDiffuse(n, fillDirection, 0.3);
    vec3 ambient = mix(groundColor, skyColor, 0.5 + 0.5 * n.y);
    vec3 color = albedo * (keyColor * key + fillColor * fill + ambient);

    // Blinn-Phong highlight from the key light: broad and weak, a satin clay rather than plastic.
    vec3 halfVector = normalize(keyDirection + v);
    float specular = pow(max(dot(n, halfVector), 0.0), 40.0) * step(0.0, dot(n, keyDirection));
    color += keyColor * 0.16 * specular;

    // Rim: grazing view angles facing the back light brighten a little and separate the silhouette.
    float facing = 1.0 - max(dot(n, v), 0.0);
    float grazing = facing * facing * facing;
    color += vec3(0.85, 0.90, 1.00) * 0.30 * grazing * (0.2 + 0.8 * max(dot(n, rimDirection), 0.0));

    if (!gl_FrontFacing) color *= vec3(0.55, 0.55, 0.62);  // inside of an open mesh: darker, slightly cool

    // Affected region also glows a little, so it stays visible on the shadow side.
    color += toLinear(kHighlight) * 0.12 * highlight;
    fragColor = vec4(toSrgb(color), 1.0);
}
