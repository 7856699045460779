// Full-screen background: one triangle that covers the viewport, no vertex buffer (gl_VertexID only).
out float vDown;  // 0 at the top edge of the viewport, 1 at the bottom

void main() {
    vec2 corner = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    vDown = 0.5 - 0.5 * corner.y;
    gl_Position = vec4(corner, 1.0, 1.0);
}
