// Mesh surface: world-space positions and per-vertex normals, shaded in view space.
//
// Built twice. The plain program reads the deformed positions and normals the CPU computed. The variant with
// GPU_DEFORMATION evaluates the deformation here instead (vertex-shader FFD, Chua & Neumann 2000): aPosition
// and aNormal are the rest position X0 and rest normal n0, uploaded once, and per frame only the lattices'
// control displacements change (uControl). Each lattice (the box cage, then the box layers after it) maps a
// point by Hu et al. 2001, eq. 1-2:
//   x = X0 + D(t),  D(t) = sum_ijk R_ijk(t) delta_ijk,  R_ijk = W_ijk B_i B_j B_k / sum W B B B,
// with t the point's lattice parameters (the cage's fixed at rest). The normal of the deformed surface is the
// rest normal carried by the map's Jacobian J = dx/dX0 (the product of each lattice's I + dD/dy): n' ~ J^-T n0,
// computed as the cofactor matrix det(J) J^-T n0 (no division, and it flips with a fold as the triangles do).
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

#ifdef GPU_DEFORMATION
// The lattices, in the order they apply: the cage (index 0), then the layers after it (session.h: the mesh shown
// is x = L_k( ... L_1( C(X0) ) )). Every one is a box lattice. Their table heads uBasis: kTableStride floats per
// lattice (integers stored as floats, exact below 2^24):
//   0-2 control points per axis, 3-5 degree per axis (1 to 5), 6-8 knot spans per axis, 9-11 where each axis's
//   span polynomials start in uBasis, 12-14 where its first-function table starts, 15 where the lattice's control
//   points start in uControl, 16-18 the box's corner (GPU frame), 19-21 spans / box size (GPU frame: the local
//   coordinate per unit of X), 22-30 the rows of the box's axes A (core/lattice.h: the identity but for a brush
//   stroke's layer, turned to its pull; the corner is then in box coordinates, (boxMin - A origin) / scale).
const int kTableStride = 32;
uniform int uLatticeCount;  // 1 + the number of layers
// Per control point id i + Nu (j + Nv k) (after the lattice's offset): displacement delta (GPU frame units) in
// xyz, NURBS weight W in w.
uniform samplerBuffer uControl;
// The table above, then per axis the basis in per-span polynomial form (bspline_basis.h,
// SplineAxis::coefficients): coefficient of x^k of basis function first(s) + i on span s at
// basisOffset + (s (p+1) + i) (p+1) + k, first(s) at firstOffset + s.
uniform samplerBuffer uBasis;

float tableEntry(int lattice, int entry) { return texelFetch(uBasis, lattice * kTableStride + entry).r; }
int tableInt(int lattice, int entry) { return int(tableEntry(lattice, entry) + 0.5); }
ivec3 tableInts(int lattice, int entry) {
    return ivec3(tableInt(lattice, entry), tableInt(lattice, entry + 1), tableInt(lattice, entry + 2));
}
vec3 tableVector(int lattice, int entry) {
    return vec3(tableEntry(lattice, entry), tableEntry(lattice, entry + 1), tableEntry(lattice, entry + 2));
}

// Per vertex: its local coordinates x in [0,1]^3 inside its knot-span cell of the cage, and the cell's index
// su + Su (sv + Sv sw) (a float, exact below 2^24), or -1 for a vertex outside the cage's box (it never moves
// there). Layers find their cell from the point itself, by their box's linear map (restParameters).
layout(location = ATTRIB_LATTICE_CELL) in vec4 aLatticeCell;

// For transform feedback (Renderer::captureGpuDeformation): the deformed position and normal, GPU frame.
out vec3 vDeformedPosition;
out vec3 vDeformedNormal;

const int kMaxOrder = 6;  // degree 5 + 1

// Values and d/dx of the p+1 basis functions non-zero on `span` at local coordinate x, by Horner's scheme on
// their polynomial coefficients; first: the id of the first of them along this axis.
void axisBasis(int lattice, int axis, int span, float x, out float value[kMaxOrder], out float slope[kMaxOrder],
               out int first) {
    int order = tableInt(lattice, 3 + axis) + 1;
    int base = tableInt(lattice, 9 + axis) + span * order * order;
    for (int i = 0; i < kMaxOrder; ++i) {
        value[i] = 0.0;
        slope[i] = 0.0;
        if (i >= order) continue;
        float v = 0.0, d = 0.0;
        for (int k = order - 1; k >= 0; --k) {
            d = d * x + v;
            v = v * x + texelFetch(uBasis, base + i * order + k).r;
        }
        value[i] = v;
        slope[i] = d;
    }
    first = int(texelFetch(uBasis, tableInt(lattice, 12 + axis) + span).r + 0.5);
}

// The box's axes A (rows in the table; GLSL's constructor takes columns, hence the transpose).
mat3 boxAxes(int lattice) {
    return transpose(mat3(tableVector(lattice, 22), tableVector(lattice, 25), tableVector(lattice, 28)));
}

// One lattice's map y -> y + D(t) at the point in knot span `span` with local coordinates `local`, and its
// Jacobian I + dD/dy multiplied onto `jacobian` (the chain rule through the lattices so far).
void applyLattice(int lattice, ivec3 span, vec3 local, inout vec3 position, inout mat3 jacobian) {
    float bu[kMaxOrder], bv[kMaxOrder], bw[kMaxOrder], du[kMaxOrder], dv[kMaxOrder], dw[kMaxOrder];
    int fu, fv, fw;
    axisBasis(lattice, 0, span.x, local.x, bu, du, fu);
    axisBasis(lattice, 1, span.y, local.y, bv, dv, fv);
    axisBasis(lattice, 2, span.z, local.z, bw, dw, fw);
    ivec3 count = tableInts(lattice, 0), degree = tableInts(lattice, 3);
    int offset = tableInt(lattice, 15);
    // Numerator N = sum W B delta and denominator S = sum W B, each with its three partials in x.
    vec3 n = vec3(0.0), nx = vec3(0.0), ny = vec3(0.0), nz = vec3(0.0);
    float s = 0.0, sx = 0.0, sy = 0.0, sz = 0.0;
    for (int k = 0; k <= degree.z; ++k) {
        for (int j = 0; j <= degree.y; ++j) {
            float b = bv[j] * bw[k], by = dv[j] * bw[k], bz = bv[j] * dw[k];
            int row = offset + fu + count.x * (fv + j + count.y * (fw + k));
            for (int i = 0; i <= degree.x; ++i) {
                vec4 control = texelFetch(uControl, row + i);
                float weight = control.w;
                float r = bu[i] * b * weight, rx = du[i] * b * weight, ry = bu[i] * by * weight,
                      rz = bu[i] * bz * weight;
                n += r * control.xyz;
                nx += rx * control.xyz;
                ny += ry * control.xyz;
                nz += rz * control.xyz;
                s += r;
                sx += rx;
                sy += ry;
                sz += rz;
            }
        }
    }
    // D = N / S and its partials by the quotient rule (S = 1, partials 0, for unit weights).
    vec3 d = n / s;
    vec3 perUnit = tableVector(lattice, 19);
    // dD/db (columns: along the box's axes), then dx/dy = I + dD/db A (A = I but for a turned box).
    mat3 dDdb = mat3((nx - d * sx) / s * perUnit.x, (ny - d * sy) / s * perUnit.y, (nz - d * sz) / s * perUnit.z);
    mat3 step = mat3(1.0) + dDdb * boxAxes(lattice);
    position += d;
    jacobian = step * jacobian;
}

// x = L_k( ... L_1( X0 + D(t) ) ) and n' = cof(J) n0 (see the top of this file).
void deform(vec3 rest, vec3 restNormal, out vec3 position, out vec3 normal) {
    position = rest;
    mat3 jacobian = mat3(1.0);
    if (aLatticeCell.w >= 0.0) {  // inside the cage's box (outside: the identity)
        int cell = int(aLatticeCell.w + 0.5);
        ivec3 spans = tableInts(0, 6);
        ivec3 span = ivec3(cell % spans.x, (cell / spans.x) % spans.y, cell / (spans.x * spans.y));
        applyLattice(0, span, aLatticeCell.xyz, position, jacobian);
    }
    for (int layer = 1; layer < uLatticeCount; ++layer) {
        // The layer's parameters of the point as it is now, times its spans: u * spans per axis.
        vec3 t = (boxAxes(layer) * position - tableVector(layer, 16)) * tableVector(layer, 19);
        ivec3 spans = tableInts(layer, 6);
        if (any(lessThan(t, vec3(0.0))) || any(greaterThan(t, vec3(spans)))) continue;  // outside its box: the identity
        ivec3 span = min(ivec3(floor(t)), spans - 1);
        applyLattice(layer, span, t - vec3(span), position, jacobian);
    }
    // Columns c_a of J: det(J) J^-T n0 = (c1 x c2) n0.x + (c2 x c0) n0.y + (c0 x c1) n0.z.
    normal = cross(jacobian[1], jacobian[2]) * restNormal.x + cross(jacobian[2], jacobian[0]) * restNormal.y +
             cross(jacobian[0], jacobian[1]) * restNormal.z;
}
#endif

void main() {
    vec3 position = aPosition;
    vec3 normal = aNormal;
#ifdef GPU_DEFORMATION
    deform(aPosition, aNormal, position, normal);
    vDeformedPosition = position;
    vDeformedNormal = normal;
#endif
    vec4 viewPosition = uView * vec4(position, 1.0);
    vViewPosition = viewPosition.xyz;
    // The view matrix is a rotation plus translation, so it maps normals too.
    vViewNormal = mat3(uView) * normal;
    vJacobian = aJacobian;
    vAffected = aAffected;
    vVertexColor = aVertexColor;
    gl_Position = uProjection * viewPosition;
}
