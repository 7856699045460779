// The det J colour map, shared by mesh.frag (the overlay) and overlay2d.frag (its legend), so the legend
// shows exactly the colours of the surface. Diverging on log(det J): equal factors of expansion and
// contraction look equally strong; interpolated in sRGB, which is closer to perceptually even than linear RGB.
uniform float uJacobianRange;  // the map saturates at 1 / uJacobianRange (blue) and uJacobianRange (red)

const vec3 kClay = vec3(0.80, 0.78, 0.74);        // the material; also det J = 1 ("unchanged")
const vec3 kExpansion = vec3(0.80, 0.11, 0.09);   // det J >= uJacobianRange: strong red
const vec3 kContraction = vec3(0.13, 0.32, 0.85); // det J <= 1 / uJacobianRange: strong blue
const vec3 kFoldA = vec3(1.0, 0.0, 1.0);          // det J <= 0: magenta ...
const vec3 kFoldB = vec3(0.0, 0.0, 0.0);          // ... and black diagonal stripes

// Position on the map of det J > 0: log(det J) / log(range), clamped to [-1, 1].
float jacobianMapPosition(float det) { return clamp(log(det) / log(uJacobianRange), -1.0, 1.0); }

// sRGB colour at map position t in [-1, 1].
vec3 jacobianMapColor(float t) {
    // note: a gentle power keeps small changes (det J 1.05) visible without saturating early.
    float s = pow(abs(t), 0.75);
    return t >= 0.0 ? mix(kClay, kExpansion, s) : mix(kClay, kContraction, s);
}

// The fold-over pattern at a window pixel: 5-pixel diagonal stripes, unlit.
vec3 foldColor(vec2 fragCoord) {
    float stripe = mod(floor((fragCoord.x + fragCoord.y) / 5.0), 2.0);
    return stripe < 1.0 ? kFoldA : kFoldB;
}
