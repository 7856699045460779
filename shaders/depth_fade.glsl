// Shared by line.vert and point.vert (prepended by the renderer): the lattice's depth cue.
// depth: normalised device depth (clip z / w: monotonic in perspective and orthographic views alike);
// fade = (depth of the lattice's nearest point, of its farthest, alpha factor at the farthest).
float depthFade(float depth, vec3 fade) {
    float t = clamp((depth - fade.x) / max(fade.y - fade.x, 1e-6), 0.0, 1.0);
    return mix(1.0, fade.z, t);
}
