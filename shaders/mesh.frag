// Mesh surface: a neutral clay material under a soft key + fill light with a slight rim, lit in linear
// RGB and written gamma-encoded (sRGB). Optional overlays recolour the albedo:
//  - det J colour map (diverging, log scale, clamped at 1/4..4; fold-over det J <= 0 is loud magenta/black)
//  - affected-region weight, tinting toward a green highlight.
// uMode 1 draws the wireframe overlay with a flat colour instead.
uniform int uMode;            // 0 shaded surface, 1 wireframe lines
uniform vec4 uWireColor;      // sRGB + alpha, for uMode 1
uniform int uShowJacobian;    // nonzero: colour by det J
uniform int uShowAffected;    // nonzero: tint by affected weight

in vec3 vViewPosition;
in vec3 vViewNormal;
in float vJacobian;
in float vAffected;
out vec4 fragColor;

// sRGB colours of the material and the maps (see the colour legend in the README).
const vec3 kClay = vec3(0.80, 0.78, 0.74);       // neutral warm grey; also det J = 1 ("unchanged")
const vec3 kExpansion = vec3(0.80, 0.11, 0.09);  // det J >= 4: strong red
const vec3 kContraction = vec3(0.13, 0.32, 0.85);// det J <= 1/4: strong blue
const vec3 kFoldA = vec3(1.0, 0.0, 1.0);         // det J <= 0: magenta ...
const vec3 kFoldB = vec3(0.0, 0.0, 0.0);         // ... and black diagonal stripes
const vec3 kHighlight = vec3(0.10, 0.85, 0.45);  // affected region: green
const vec3 kHighlightLine = vec3(0.02, 0.30, 0.14); // its boundary and half-weight iso-lines: dark green
const float kJacobianClamp = 4.0;                // the map saturates at 1/4 and 4

vec3 toLinear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 toSrgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

// Diverging map on log(det J): equal factors of expansion and contraction look equally strong.
// Interpolated in sRGB, which is closer to perceptually even than linear RGB.
vec3 jacobianColor(float det) {
    float t = clamp(log(det) / log(kJacobianClamp), -1.0, 1.0);
    // note: a gentle power keeps small changes (det J 1.1) visible without saturating early.
    float s = pow(abs(t), 0.75);
    return t >= 0.0 ? mix(kClay, kExpansion, s) : mix(kClay, kContraction, s);
}

// 1 on the iso-line value == level (about one pixel wide), 0 away from it.
float isoLine(float value, float level) {
    float width = max(fwidth(value), 1e-6);  // value is a weight in [0, 1], not a length: no unit involved
    return 1.0 - clamp(abs(value - level) / width, 0.0, 1.0);
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
        // Thin darker iso-lines at the edge of the region (weight 0.02) and at half influence.
        affectedLines = max(isoLine(vAffected, 0.02), 0.6 * isoLine(vAffected, 0.5));
    }
    if (uShowJacobian != 0 && !(vJacobian > 0.0)) {
        // Fold-over (or NaN): unlit stripes, so it cannot be mistaken for shading or missed in a shadow.
        float stripe = mod(floor((gl_FragCoord.x + gl_FragCoord.y) / 5.0), 2.0);
        fragColor = vec4(stripe < 1.0 ? kFoldA : kFoldB, 1.0);
        return;
    }
    // note: the plain material's linear albedo is a constant the compiler folds; overlays pay for pow().
    vec3 albedo = toLinear(kClay);
    float highlight = 0.0;
    if (uShowJacobian != 0 || uShowAffected != 0) {
        vec3 albedoSrgb = uShowJacobian != 0 ? jacobianColor(vJacobian) : kClay;
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
