// Mesh surface: world-space positions and per-vertex normals, shaded in view space.
layout(location = ATTRIB_POSITION) in vec3 aPosition;
layout(location = ATTRIB_NORMAL) in vec3 aNormal;
layout(location = ATTRIB_JACOBIAN) in float aJacobian;
layout(location = ATTRIB_AFFECTED) in float aAffected;
layout(location = ATTRIB_VERTEX_COLOR) in vec3 aVertexColor;

uniform mat4 uView;
uniform mat4 uProjection;

out vec3 vViewPosition;
out vec3 vViewNormal;
out float vJacobian;
out float vAffected;
out vec3 vVertexColor;

void main() {
    vec4 viewPosition = uView * vec4(aPosition, 1.0);
    vViewPosition = viewPosition.xyz;
    // The view matrix is a rotation plus translation, so it maps normals too.
    vViewNormal = mat3(uView) * aNormal;
    vJacobian = aJacobian;
    vAffected = aAffected;
    vVertexColor = aVertexColor;
    gl_Position = uProjection * viewPosition;
}
