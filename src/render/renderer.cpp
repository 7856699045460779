#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <omp.h>

#include <glm/gtc/type_ptr.hpp>

#include "core/vertex_normals.h"
#include "render/gl_functions.h"
#include "render/legend.h"
#include "render/overlay_geometry.h"
#include "render/palette.h"
#include "render/shader_program.h"

namespace sculpt::render {

namespace {

// More than this fraction of changed vertices: recompute all normals and rewrite the whole buffer.
constexpr int kFullUploadDivisor = 4;
// Changed vertex runs closer than this many vertices are uploaded as one range (fewer GL calls).
constexpr int kRangeMergeGap = 32;

constexpr int kVertexFloats = 6;  // position xyz, normal xyz

struct InstanceBatch {
    GLuint vao = 0;
    GLuint buffer = 0;
    int count = 0;
};

struct MeshUniforms {
    GLint view = -1, projection = -1, mode = -1, wireColor = -1, showJacobian = -1, showAffected = -1, jacobianRange = -1,
          showVertexColors = -1;
};
// The GPU_DEFORMATION variant's own uniforms (shaders/mesh.vert).
struct DeformUniforms {
    GLint control = -1, basis = -1, latticeCount = -1;
};
// The most layers the GPU path takes after the cage: each costs every vertex a box test in the shader.
constexpr int kMaxGpuLayers = 1024;
// mesh.vert's lattice table: floats per lattice at the head of the basis buffer.
constexpr int kLatticeTableStride = 32;
// A lattice's shape on the GPU path: what the cage's per-frame update must match (its cells are per vertex).
struct GpuLatticeShape {
    std::array<int, 3> count{}, degree{}, spans{};
    Eigen::Vector3d boxMin = Eigen::Vector3d::Zero(), boxMax = Eigen::Vector3d::Zero();
    bool sameLattice(const GpuLatticeShape& o) const {
        return count == o.count && degree == o.degree && spans == o.spans && boxMin == o.boxMin && boxMax == o.boxMax;
    }
};
// Transform feedback of the GPU path: position and normal per vertex (captureGpuDeformation).
constexpr int kFeedbackFloats = 6;
struct OverlayUniforms {
    GLint viewport = -1, jacobianRange = -1;
};
struct BackgroundUniforms {
    GLint topColor = -1, bottomColor = -1;
};
struct LineUniforms {
    GLint viewProjection = -1, viewport = -1, width = -1, tint = -1, alphaScale = -1, depthFade = -1;
};
struct PointUniforms {
    GLint viewProjection = -1, viewport = -1, sizeScale = -1, alphaScale = -1, depthFade = -1, crowdScale = -1;
};

constexpr Rgba kNoTint = {0, 0, 0, 0};  // lines keep their per-vertex colours
// The depth cue's uniform (shaders/depth_fade.glsl) that leaves alpha as it is.
constexpr glm::vec3 kNoDepthFade(0.0f, 1.0f, 1.0f);

std::string glErrorText(GLenum error) {
    switch (error) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        default: return "GL error " + std::to_string(error);
    }
}

}  // namespace

struct Renderer::State {
    GlFunctions gl;
    bool ready = false;
    float pixelScale = 1.0f;

    GLuint backgroundProgram = 0, meshProgram = 0, lineProgram = 0, pointProgram = 0, overlayProgram = 0;
    GLuint deformProgram = 0;  // mesh.vert with GPU_DEFORMATION
    MeshUniforms deformMeshUniforms;
    DeformUniforms deformUniforms;
    // The GPU path: per-vertex cell + local coordinates, and two buffer textures (control points, basis).
    GLuint cellBuffer = 0, controlBuffer = 0, controlTexture = 0, basisBuffer = 0, basisTexture = 0;
    bool gpuDeformation = false;
    GpuLatticeShape gpuCage;  // the cage the GPU path was set up with
    int gpuLatticeCount = 0;  // the cage and its layers, as last uploaded
    // As uploaded: the lattice table and bases (basisBuffer), the control points (controlBuffer).
    std::vector<float> basisData, controlData;
    BackgroundUniforms backgroundUniforms;
    OverlayUniforms overlayUniforms;
    GLuint overlayVao = 0, overlayBuffer = 0;  // flat screen-space triangles (the det J legend), rebuilt per draw
    MeshUniforms meshUniforms;
    LineUniforms lineUniforms;
    PointUniforms pointUniforms;
    GLuint emptyVao = 0;  // core profile draws need a bound VAO even without attributes

    // Mesh on the GPU: interleaved position + normal records, 32-bit indices, optional fields.
    GLuint meshVao = 0, vertexBuffer = 0, indexBuffer = 0, jacobianBuffer = 0, affectedBuffer = 0, colorBuffer = 0;
    bool hasJacobian = false, hasAffected = false, hasVertexColors = false;
    // The element buffer holds the full mesh's triangles, then the proxy's (mesh_proxy.h; none for a small mesh).
    GLsizei proxyIndexCount = 0;
    MeshProxyOptions proxyOptions;
    mutable int lastDrawnTriangles = 0;
    // ... and the CPU copy that sparse updates start from.
    Positions positions, normals;
    Triangles triangles;
    core::VertexTriangles adjacency;
    std::vector<std::uint8_t> staleMarks;  // #V, all zero between updates
    std::vector<float> staging;
    UploadStats lastUpload;

    InstanceBatch latticeEdges, latticePoints, handleLines, handlePoints;
    Bounds latticeBounds;
    // The unselected control-point markers' centres (local frame), for their crowding on screen
    // (crowdedMarkerScale), and the factor of the last draw with the view it was computed for.
    std::vector<glm::vec3> plainMarkerCentres;
    mutable float crowdScale = 1.0f;
    mutable glm::mat4 crowdViewProjection{0.0f};
    mutable glm::ivec2 crowdViewport{0};
    mutable bool crowdStale = true;
    // The frame the GPU coordinates are in (camera.h): the mesh's centre and radius when it was set (the
    // lattice's while there is no mesh). The overlays are kept in world units too, so that a new frame can
    // re-express them.
    LocalFrame frame;
    LatticeView lattice;
    ConstraintView constraints;

    GLint uniform(GLuint program, const char* name) const { return gl.GetUniformLocation(program, name); }
    // The uniforms of shaders/mesh.frag and mesh.vert that both mesh programs (CPU and GPU path) have.
    MeshUniforms meshUniformsOf(GLuint program) const {
        return {uniform(program, "uView"),          uniform(program, "uProjection"),   uniform(program, "uMode"),
                uniform(program, "uWireColor"),     uniform(program, "uShowJacobian"), uniform(program, "uShowAffected"),
                uniform(program, "uJacobianRange"), uniform(program, "uShowVertexColors")};
    }
    // Off the GPU path: the mesh draws the vertex buffer's positions again (the caller has put them there).
    void leaveGpuPath();
    // Into staging, vertices [first, last) of the given arrays (the kept positions and normals by default).
    void packVertices(int first, int last) { packVertices(first, last, positions, normals); }
    void packVertices(int first, int last, const Positions& from, const Positions& fromNormals);
    // Recomputes every normal of the kept positions and rewrites the whole vertex buffer.
    void uploadAllVertices();
    // The lattices' control displacements (GPU frame units) and weights into controlBuffer, and their basis
    // into basisBuffer where it changed; records the cage's shape and the lattice count.
    void uploadLattices(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers);
    void uploadVertexRange(int first, int last);
    Status buildPrograms();
    void createObjects();
    void setupInstanceBatch(InstanceBatch& batch, const GLuint* locations, const GLint* sizes, int count);
    void setupLineBatch(InstanceBatch& batch);
    void setupPointBatch(InstanceBatch& batch);
    void uploadBatch(InstanceBatch& batch, const std::vector<float>& data, int floatsPerInstance);
    // Rebuilds the lattice and constraint batches from the kept (already validated) views in `frame`.
    void uploadOverlays();
    void drawLines(const InstanceBatch& batch, const glm::mat4& viewProjection, int width, int height,
                   float lineWidth, const Rgba& tint, float alphaScale, const glm::vec3& depthFade = kNoDepthFade) const;
    void drawPoints(const InstanceBatch& batch, const glm::mat4& viewProjection, int width, int height,
                    float alphaScale, const glm::vec3& depthFade = kNoDepthFade, float crowd = 1.0f) const;
    // Keeps the lattice markers' batch and their centres for crowdedMarkerScale.
    void uploadLatticeMarkers(const std::vector<float>& markers);
    // crowdedMarkerScale of the plain markers in this view (cached while the view and the lattice stay).
    float markerCrowding(const glm::mat4& viewProjection, int width, int height) const;
    // The det J legend in the bottom-right corner (legend.h), over everything.
    void drawJacobianLegend(const DrawOptions& options, int width, int height) const;
    // The GPU path's uniforms and buffer textures (units 0 and 1) for deformProgram, in use; and undone.
    void bindGpuDeformation() const;
    void unbindGpuDeformation() const;
    // The lattice overlay: edges and control points, the parts behind the mesh fainter, faded with depth.
    void drawLattice(const glm::mat4& view, const glm::mat4& projection, int width, int height) const;
};

Renderer::Renderer() : state_(std::make_unique<State>()) {}
Renderer::~Renderer() = default;

bool Renderer::initialized() const { return state_->ready; }

Status Renderer::init(GlGetProc getProc) {
    GlFunctions gl;
    if (Status status = loadGlFunctions(getProc, gl); !status) return status;
    return init(gl);
}

Status Renderer::init(const GlFunctions& gl) {
    release();
    state_->gl = gl;
    if (Status status = checkGlVersion(gl, nullptr); !status) return status;
    // Errors left by whoever used the context before us are not ours. (Bounded: a lost context may report
    // GL_CONTEXT_LOST forever.)
    for (int i = 0; i < 32 && gl.GetError() != GL_NO_ERROR; ++i) {
    }
    if (Status status = state_->buildPrograms(); !status) {
        release();
        return status;
    }
    state_->createObjects();
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR) {
        release();
        return Status::error("creating the renderer's GL objects failed: " + glErrorText(error));
    }
    state_->ready = true;
    return Status::success();
}

Status Renderer::State::buildPrograms() {
    if (Status status = buildEmbeddedProgram(gl, "background", backgroundProgram); !status) return status;
    if (Status status = buildEmbeddedProgram(gl, "mesh", meshProgram); !status) return status;
    if (Status status = buildEmbeddedProgram(gl, "line", lineProgram); !status) return status;
    if (Status status = buildEmbeddedProgram(gl, "point", pointProgram); !status) return status;
    if (Status status = buildEmbeddedProgram(gl, "overlay2d", overlayProgram); !status) return status;
    ProgramOptions deformOptions;
    deformOptions.defines = "#define GPU_DEFORMATION 1\n";
    deformOptions.feedbackVaryings = {"vDeformedPosition", "vDeformedNormal"};
    if (Status status = buildEmbeddedProgram(gl, "mesh", deformOptions, deformProgram); !status) return status;
    deformMeshUniforms = meshUniformsOf(deformProgram);
    deformUniforms = {uniform(deformProgram, "uControl"), uniform(deformProgram, "uBasis"),
                      uniform(deformProgram, "uLatticeCount")};
    backgroundUniforms = {uniform(backgroundProgram, "uTopColor"), uniform(backgroundProgram, "uBottomColor")};
    meshUniforms = meshUniformsOf(meshProgram);
    overlayUniforms = {uniform(overlayProgram, "uViewport"), uniform(overlayProgram, "uJacobianRange")};
    lineUniforms = {uniform(lineProgram, "uViewProjection"), uniform(lineProgram, "uViewport"),
                    uniform(lineProgram, "uWidth"), uniform(lineProgram, "uTint"),
                    uniform(lineProgram, "uAlphaScale"), uniform(lineProgram, "uDepthFade")};
    pointUniforms = {uniform(pointProgram, "uViewProjection"), uniform(pointProgram, "uViewport"),
                     uniform(pointProgram, "uSizeScale"), uniform(pointProgram, "uAlphaScale"),
                     uniform(pointProgram, "uDepthFade"), uniform(pointProgram, "uCrowdScale")};
    return Status::success();
}

void Renderer::State::createObjects() {
    gl.GenVertexArrays(1, &emptyVao);

    gl.GenVertexArrays(1, &meshVao);
    gl.GenBuffers(1, &vertexBuffer);
    gl.GenBuffers(1, &indexBuffer);
    gl.GenBuffers(1, &jacobianBuffer);
    gl.GenBuffers(1, &affectedBuffer);
    gl.GenBuffers(1, &colorBuffer);
    gl.BindVertexArray(meshVao);
    gl.BindBuffer(GL_ARRAY_BUFFER, vertexBuffer);
    const GLsizei stride = kVertexFloats * sizeof(float);
    gl.EnableVertexAttribArray(kAttribPosition);
    gl.VertexAttribPointer(kAttribPosition, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    gl.EnableVertexAttribArray(kAttribNormal);
    gl.VertexAttribPointer(kAttribNormal, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
    gl.BindBuffer(GL_ARRAY_BUFFER, jacobianBuffer);
    gl.VertexAttribPointer(kAttribJacobian, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.BindBuffer(GL_ARRAY_BUFFER, affectedBuffer);
    gl.VertexAttribPointer(kAttribAffected, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.BindBuffer(GL_ARRAY_BUFFER, colorBuffer);
    gl.VertexAttribPointer(kAttribVertexColor, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.GenBuffers(1, &cellBuffer);
    gl.BindBuffer(GL_ARRAY_BUFFER, cellBuffer);
    gl.VertexAttribPointer(kAttribLatticeCell, 4, GL_FLOAT, GL_FALSE, 0, nullptr);  // enabled on the GPU path
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer);  // recorded in the VAO
    gl.BindVertexArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);

    for (auto [buffer, texture] : {std::pair{&controlBuffer, &controlTexture}, std::pair{&basisBuffer, &basisTexture}}) {
        gl.GenBuffers(1, buffer);
        gl.GenTextures(1, texture);
    }

    setupLineBatch(latticeEdges);
    setupLineBatch(handleLines);
    setupPointBatch(latticePoints);
    setupPointBatch(handlePoints);

    gl.GenVertexArrays(1, &overlayVao);
    gl.GenBuffers(1, &overlayBuffer);
    gl.BindVertexArray(overlayVao);
    gl.BindBuffer(GL_ARRAY_BUFFER, overlayBuffer);
    const GLsizei overlayStride = kOverlayFloats * sizeof(float);
    static_assert(2 + 4 + 2 == kOverlayFloats, "overlay vertex layout");
    gl.EnableVertexAttribArray(kAttribOverlayPixel);
    gl.VertexAttribPointer(kAttribOverlayPixel, 2, GL_FLOAT, GL_FALSE, overlayStride, nullptr);
    gl.EnableVertexAttribArray(kAttribOverlayColor);
    gl.VertexAttribPointer(kAttribOverlayColor, 4, GL_FLOAT, GL_FALSE, overlayStride, reinterpret_cast<void*>(2 * sizeof(float)));
    gl.EnableVertexAttribArray(kAttribOverlayFill);
    gl.VertexAttribPointer(kAttribOverlayFill, 2, GL_FLOAT, GL_FALSE, overlayStride, reinterpret_cast<void*>(6 * sizeof(float)));
    gl.BindVertexArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
}

// An instanced batch: one buffer of interleaved per-instance float attributes (one row per segment/marker).
void Renderer::State::setupInstanceBatch(InstanceBatch& batch, const GLuint* locations, const GLint* sizes, int count) {
    gl.GenVertexArrays(1, &batch.vao);
    gl.GenBuffers(1, &batch.buffer);
    gl.BindVertexArray(batch.vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, batch.buffer);
    GLsizei stride = 0;
    for (int a = 0; a < count; ++a) stride += GLsizei(sizes[a] * sizeof(float));
    size_t offset = 0;
    for (int a = 0; a < count; ++a) {
        gl.EnableVertexAttribArray(locations[a]);
        gl.VertexAttribPointer(locations[a], sizes[a], GL_FLOAT, GL_FALSE, stride,
                               reinterpret_cast<void*>(offset * sizeof(float)));
        gl.VertexAttribDivisor(locations[a], 1);
        offset += size_t(sizes[a]);
    }
    gl.BindVertexArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
}

void Renderer::State::setupLineBatch(InstanceBatch& batch) {
    const GLuint locations[4] = {kAttribSegmentStart, kAttribSegmentEnd, kAttribColorStart, kAttribColorEnd};
    const GLint sizes[4] = {3, 3, 4, 4};
    static_assert(3 + 3 + 4 + 4 == kLineFloats, "line instance layout");
    setupInstanceBatch(batch, locations, sizes, 4);
}

void Renderer::State::setupPointBatch(InstanceBatch& batch) {
    const GLuint locations[3] = {kAttribMarkerCenter, kAttribMarkerColor, kAttribMarkerStyle};
    const GLint sizes[3] = {3, 4, 3};
    static_assert(3 + 4 + 3 == kMarkerFloats, "marker instance layout");
    setupInstanceBatch(batch, locations, sizes, 3);
}

void Renderer::State::uploadBatch(InstanceBatch& batch, const std::vector<float>& data, int floatsPerInstance) {
    gl.BindBuffer(GL_ARRAY_BUFFER, batch.buffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.empty() ? nullptr : data.data(),
                  GL_DYNAMIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    batch.count = int(data.size()) / floatsPerInstance;
}

void Renderer::release() {
    State& s = *state_;
    // Also after a failed init, which may have created some objects (glDelete* ignores name 0).
    if (s.gl.DeleteProgram) {
        const GlFunctions& gl = s.gl;
        for (GLuint program : {s.backgroundProgram, s.meshProgram, s.lineProgram, s.pointProgram, s.overlayProgram,
                               s.deformProgram})
            if (program) gl.DeleteProgram(program);
        for (GLuint* vao : {&s.emptyVao, &s.meshVao, &s.latticeEdges.vao, &s.latticePoints.vao, &s.handleLines.vao,
                            &s.handlePoints.vao, &s.overlayVao})
            gl.DeleteVertexArrays(1, vao);
        for (GLuint* buffer : {&s.vertexBuffer, &s.indexBuffer, &s.jacobianBuffer, &s.affectedBuffer, &s.colorBuffer,
                               &s.latticeEdges.buffer, &s.latticePoints.buffer, &s.handleLines.buffer,
                               &s.handlePoints.buffer, &s.overlayBuffer, &s.cellBuffer, &s.controlBuffer, &s.basisBuffer})
            gl.DeleteBuffers(1, buffer);
        for (GLuint* texture : {&s.controlTexture, &s.basisTexture}) gl.DeleteTextures(1, texture);
    }
    const float pixelScale = s.pixelScale;
    const MeshProxyOptions proxyOptions = s.proxyOptions;
    *state_ = State{};
    state_->pixelScale = pixelScale;
    state_->proxyOptions = proxyOptions;
}

// ---- mesh ----------------------------------------------------------------------------------------

void Renderer::State::packVertices(int first, int last, const Positions& from, const Positions& fromNormals) {
    staging.resize(size_t(last - first) * kVertexFloats);
    float* out = staging.data();
    // note: the origin is subtracted in double, before the conversion to float (camera.h, LocalFrame).
    const glm::dvec3 origin = frame.origin;
    const double inverseScale = 1.0 / frame.scale;
#pragma omp parallel for schedule(static) if (last - first > 65536)
    for (int v = first; v < last; ++v) {
        float* record = out + size_t(v - first) * kVertexFloats;
        for (int c = 0; c < 3; ++c) {
            record[c] = float((from(v, c) - origin[c]) * inverseScale);
            record[3 + c] = float(fromNormals(v, c));
        }
    }
}

void Renderer::State::uploadVertexRange(int first, int last) {
    packVertices(first, last);
    gl.BufferSubData(GL_ARRAY_BUFFER, GLintptr(first) * kVertexFloats * GLintptr(sizeof(float)),
                     GLsizeiptr(staging.size() * sizeof(float)), staging.data());
}

Status Renderer::setMesh(const Positions& positions, const Triangles& triangles) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (Status status = checkFinite(positions, "mesh position"); !status) return status;
    const Eigen::Index vertexCount = positions.rows();
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int c = 0; c < 3; ++c)
            if (triangles(t, c) < 0 || triangles(t, c) >= vertexCount)
                return Status::error("triangle " + std::to_string(t) + " has vertex index " +
                                     std::to_string(triangles(t, c)) + ", outside [0, " +
                                     std::to_string(vertexCount) + ")");
    s.positions = positions;
    s.triangles = triangles;
    if (s.gpuDeformation) s.leaveGpuPath();
    if (vertexCount > 0) {
        const LocalFrame frame = localFrameOf(boundsOf(s.positions));
        if (frame != s.frame) {
            s.frame = frame;
            s.uploadOverlays();
        }
    }
    core::computeVertexNormals(s.positions, s.triangles, s.normals);
    s.adjacency = core::buildVertexTriangles(int(vertexCount), s.triangles);
    s.staleMarks.assign(size_t(vertexCount), 0);

    const GlFunctions& gl = s.gl;
    s.packVertices(0, int(vertexCount));
    gl.BindBuffer(GL_ARRAY_BUFFER, s.vertexBuffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(s.staging.size() * sizeof(float)),
                  s.staging.empty() ? nullptr : s.staging.data(), GL_DYNAMIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    gl.BindVertexArray(s.meshVao);  // the element buffer binding belongs to the VAO
    // note: Triangles is row-major int; validated non-negative, so its bytes are valid GL_UNSIGNED_INT indices.
    const Triangles proxy = buildMeshProxy(s.positions, s.triangles, s.proxyOptions);
    const GLsizeiptr fullBytes = GLsizeiptr(s.triangles.size() * sizeof(int));
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, fullBytes + GLsizeiptr(proxy.size() * sizeof(int)),
                  nullptr, GL_STATIC_DRAW);
    if (fullBytes > 0) gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, fullBytes, s.triangles.data());
    if (proxy.size() > 0)
        gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, fullBytes, GLsizeiptr(proxy.size() * sizeof(int)), proxy.data());
    s.proxyIndexCount = GLsizei(proxy.size());
    gl.BindVertexArray(0);
    s.lastUpload = {int(vertexCount), 1, true};
    setJacobianField({});
    setAffectedWeights({});
    setVertexColors({});
    s.staging.clear();
    s.staging.shrink_to_fit();
    return Status::success();
}

Status Renderer::updatePositions(const Positions& positions, const std::vector<int>& changedVertices) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (s.gpuDeformation)
        return Status::error("updatePositions: the mesh is deformed on the GPU; send the lattice "
                             "(updateGpuDeformation) or leave the GPU path first (clearGpuDeformation)");
    const int vertexCount = int(s.positions.rows());
    if (positions.rows() != vertexCount)
        return Status::error("updatePositions: " + std::to_string(positions.rows()) +
                             " positions given for a mesh of " + std::to_string(vertexCount) + " vertices");
    // Checked in parallel (a global change lists every vertex); the first bad entry is the one reported.
    const int changedCount = int(changedVertices.size());
    int firstBad = changedCount;
#pragma omp parallel for schedule(static) reduction(min : firstBad) if (changedCount > 65536)
    for (int i = 0; i < changedCount; ++i) {
        const int v = changedVertices[size_t(i)];
        if (v < 0 || v >= vertexCount || !positions.row(v).allFinite()) firstBad = std::min(firstBad, i);
    }
    if (firstBad < changedCount) {
        const int v = changedVertices[size_t(firstBad)];
        if (v < 0 || v >= vertexCount)
            return Status::error("updatePositions: changed vertex " + std::to_string(v) + " is outside [0, " +
                                 std::to_string(vertexCount) + ")");
        return Status::error("updatePositions: position of vertex " + std::to_string(v) +
                             " is not finite (NaN or infinity); nothing was uploaded");
    }
    s.lastUpload = {};
    if (changedVertices.empty()) return Status::success();
    if (changedCount > 65536) {
        // Each thread copies the listed rows that fall in its own block of vertex ids: no two threads write
        // one row, even when the list repeats a vertex.
#pragma omp parallel
        {
            const int threads = omp_get_num_threads(), thread = omp_get_thread_num();
            const int first = int(int64_t(vertexCount) * thread / threads);
            const int last = int(int64_t(vertexCount) * (thread + 1) / threads);
            for (int v : changedVertices)
                if (v >= first && v < last) s.positions.row(v) = positions.row(v);
        }
    } else {
        for (int v : changedVertices) s.positions.row(v) = positions.row(v);
    }

    const GlFunctions& gl = s.gl;
    gl.BindBuffer(GL_ARRAY_BUFFER, s.vertexBuffer);
    if (changedVertices.size() * kFullUploadDivisor > size_t(vertexCount)) {
        s.uploadAllVertices();
    } else {
        core::updateVertexNormals(s.positions, s.triangles, s.adjacency, changedVertices, s.normals);
        // Stale records: each changed vertex (position) and every vertex sharing a triangle with it (normal),
        // the same ring updateVertexNormals recomputed.
        int lowest = vertexCount, highest = -1;
        const auto mark = [&](int v) {
            s.staleMarks[size_t(v)] = 1;
            lowest = std::min(lowest, v);
            highest = std::max(highest, v);
        };
        for (int v : changedVertices) {
            mark(v);
            for (int k = s.adjacency.offsets[v]; k < s.adjacency.offsets[v + 1]; ++k)
                for (int c = 0; c < 3; ++c) mark(s.triangles(s.adjacency.triangles[k], c));
        }
        // Contiguous runs of marked vertices, merged across small gaps, one glBufferSubData each.
        int runStart = -1, lastMarked = -1;
        for (int v = lowest; v <= highest; ++v) {
            if (!s.staleMarks[size_t(v)]) continue;
            s.staleMarks[size_t(v)] = 0;
            if (runStart >= 0 && v - lastMarked > kRangeMergeGap) {
                s.uploadVertexRange(runStart, lastMarked + 1);
                s.lastUpload.verticesUploaded += lastMarked + 1 - runStart;
                ++s.lastUpload.ranges;
                runStart = -1;
            }
            if (runStart < 0) runStart = v;
            lastMarked = v;
        }
        if (runStart >= 0) {
            s.uploadVertexRange(runStart, lastMarked + 1);
            s.lastUpload.verticesUploaded += lastMarked + 1 - runStart;
            ++s.lastUpload.ranges;
        }
    }
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    return Status::success();
}

void Renderer::State::uploadAllVertices() {
    const int vertexCount = int(positions.rows());
    core::computeVertexNormals(positions, triangles, adjacency, normals);
    packVertices(0, vertexCount);
    gl.BindBuffer(GL_ARRAY_BUFFER, vertexBuffer);
    // Re-specifying the whole store lets the driver orphan the old one instead of waiting for draws.
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(staging.size() * sizeof(float)), staging.data(), GL_DYNAMIC_DRAW);
    lastUpload = {vertexCount, 1, true};
}

// ---- the deformation on the GPU ------------------------------------------------------------------

std::string Renderer::gpuDeformationProblem(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers) {
    if (cage.volume)
        return "a " + cage.volume->kindName() + " lattice is deformed on the CPU (the GPU path takes box lattices)";
    if (cage.controlPointCount() <= 0) return "there is no lattice";
    if (int(layers.size()) > kMaxGpuLayers)
        return std::to_string(layers.size()) + " layers are deformed on the CPU (the GPU path takes up to " +
               std::to_string(kMaxGpuLayers) + ")";
    for (const core::Lattice* layer : layers)
        if (!layer || layer->volume || layer->controlPointCount() <= 0)
            return "a layer that is not a box lattice is deformed on the CPU";
    return {};
}

namespace {

// Checks one lattice's arrays for the GPU path (sizes, finite values); `what` names it in the message.
Status checkGpuLatticeValues(const core::Lattice& lattice, const std::string& what) {
    const Eigen::Index points = lattice.controlPointCount();
    if (lattice.displacement.rows() != points || Eigen::Index(lattice.weights.size()) != points)
        return Status::error("GPU deformation: " + what + " has " + std::to_string(points) + " control points but " +
                             std::to_string(lattice.displacement.rows()) + " displacements and " +
                             std::to_string(lattice.weights.size()) + " weights");
    for (Eigen::Index i = 0; i < points; ++i) {
        if (!lattice.displacement.row(i).allFinite())
            return Status::error("GPU deformation: the displacement of control point " + lattice.controlPointName(int(i)) +
                                 " of " + what + " is not finite");
        if (!(lattice.weights[size_t(i)] > 0.0) || !std::isfinite(lattice.weights[size_t(i)]))
            return Status::error("GPU deformation: the weight of control point " + lattice.controlPointName(int(i)) +
                                 " of " + what + " is not a finite positive number");
    }
    if (!lattice.boxMin.allFinite() || !lattice.boxMax.allFinite() || !((lattice.boxMax - lattice.boxMin).array() > 0.0).all())
        return Status::error("GPU deformation: the box of " + what + " is empty or not finite");
    return Status::success();
}

// The kinds first, then every lattice's values.
Status checkGpuLattices(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers) {
    if (std::string problem = Renderer::gpuDeformationProblem(cage, layers); !problem.empty())
        return Status::error("GPU deformation: " + problem);
    if (Status status = checkGpuLatticeValues(cage, "the lattice"); !status) return status;
    for (size_t k = 0; k < layers.size(); ++k)
        if (Status status = checkGpuLatticeValues(*layers[k], "layer " + std::to_string(k + 1)); !status) return status;
    return Status::success();
}

GpuLatticeShape shapeOf(const core::Lattice& lattice) {
    GpuLatticeShape shape;
    shape.count = lattice.count;
    shape.degree = lattice.degree;
    shape.spans = lattice.spans();
    shape.boxMin = lattice.boxMin;
    shape.boxMax = lattice.boxMax;
    return shape;
}

}  // namespace

void Renderer::State::uploadLattices(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers) {
    std::vector<const core::Lattice*> all{&cage};
    all.insert(all.end(), layers.begin(), layers.end());
    // The table first (mesh.vert), then each lattice's bases: each axis's span polynomials and first functions.
    std::vector<float> basis(all.size() * kLatticeTableStride, 0.0f);
    std::vector<int> controlOffset(all.size() + 1, 0);
    for (size_t l = 0; l < all.size(); ++l) {
        const core::Lattice& source = *all[l];
        const GpuLatticeShape shape = shapeOf(source);
        const size_t row = l * kLatticeTableStride;
        // The GPU frame's origin in the box's coordinates (itself for an unturned box).
        const Eigen::Vector3d turnedOrigin = core::toBoxCoordinates(source, Eigen::Vector3d(frame.origin[0], frame.origin[1], frame.origin[2]));
        for (int a = 0; a < 3; ++a) {
            const core::SplineAxis& axis = source.axes[size_t(a)];
            basis[row + 9 + size_t(a)] = float(basis.size());
            for (double c : axis.coefficients) basis.push_back(float(c));
            basis[row + 12 + size_t(a)] = float(basis.size());
            for (int span = 0; span < axis.spans; ++span) basis.push_back(float(axis.first(span)));
            basis[row + size_t(a)] = float(shape.count[size_t(a)]);
            basis[row + 3 + size_t(a)] = float(shape.degree[size_t(a)]);
            basis[row + 6 + size_t(a)] = float(shape.spans[size_t(a)]);
            // The box in the GPU frame, and the local coordinate per unit there: spans over the box's size. A
            // turned box (a brush stroke's, core/lattice.h): its corner in box coordinates relative to the turned
            // origin, (boxMin - A origin) / scale, and A's rows at 22-30, so t = (A p - corner) * perUnit.
            basis[row + 16 + size_t(a)] = float((shape.boxMin[a] - turnedOrigin[a]) / frame.scale);
            for (int c = 0; c < 3; ++c) basis[row + 22 + size_t(3 * a + c)] = float(source.boxAxes(a, c));
            basis[row + 19 + size_t(a)] =
                float(double(shape.spans[size_t(a)]) * frame.scale / (shape.boxMax[a] - shape.boxMin[a]));
        }
        basis[row + 15] = float(controlOffset[l]);
        controlOffset[l + 1] = controlOffset[l] + source.controlPointCount();
    }
    gpuCage = shapeOf(cage);
    gpuLatticeCount = int(all.size());
    const int controlCount = controlOffset.back();
    std::vector<float> control(size_t(controlCount) * 4);
    const double inverseScale = 1.0 / frame.scale;  // displacements are differences: no origin
    for (size_t l = 0; l < all.size(); ++l) {
        const core::Lattice& source = *all[l];
        float* out = control.data() + size_t(controlOffset[l]) * 4;
        for (int i = 0; i < source.controlPointCount(); ++i) {
            for (int c = 0; c < 3; ++c) out[size_t(i) * 4 + size_t(c)] = float(source.displacement(i, c) * inverseScale);
            out[size_t(i) * 4 + 3] = float(source.weights[size_t(i)]);
        }
    }
    // Only what changed goes up: during a drag, the one lattice being solved (many layers stay as they are).
    gl.BindBuffer(GL_TEXTURE_BUFFER, controlBuffer);
    if (control.size() != controlData.size()) {
        gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(control.size() * sizeof(float)), control.data(), GL_STREAM_DRAW);
        lastUpload.controlPointsUploaded = controlCount;
    } else {
        const auto first = std::mismatch(control.begin(), control.end(), controlData.begin()).first - control.begin();
        if (first < std::ptrdiff_t(control.size())) {
            std::ptrdiff_t last = std::ptrdiff_t(control.size());
            while (control[size_t(last - 1)] == controlData[size_t(last - 1)]) --last;
            const std::ptrdiff_t from = first / 4 * 4, to = (last + 3) / 4 * 4;  // whole control points
            gl.BufferSubData(GL_TEXTURE_BUFFER, GLintptr(from) * GLintptr(sizeof(float)), GLsizeiptr(to - from) * GLsizeiptr(sizeof(float)),
                             control.data() + from);
            lastUpload.controlPointsUploaded = int((to - from) / 4);
        }
    }
    controlData = std::move(control);
    if (basis != basisData) {  // a layer came or went: the table and bases go up too
        basisData = std::move(basis);
        gl.BindBuffer(GL_TEXTURE_BUFFER, basisBuffer);
        gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(basisData.size() * sizeof(float)), basisData.data(), GL_STATIC_DRAW);
    }
    gl.BindBuffer(GL_TEXTURE_BUFFER, 0);
}

Status Renderer::setGpuDeformation(const core::Lattice& lattice, const core::Embedding& embedding, const Positions& rest,
                                   const std::vector<const core::Lattice*>& layers) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    const int vertexCount = int(s.positions.rows());
    if (vertexCount == 0) return Status::error("GPU deformation: there is no mesh");
    if (rest.rows() != vertexCount || embedding.vertexCount != vertexCount)
        return Status::error("GPU deformation: " + std::to_string(rest.rows()) + " rest positions and an embedding of " +
                             std::to_string(embedding.vertexCount) + " vertices for a mesh of " +
                             std::to_string(vertexCount) + " vertices");
    if (Status status = checkFinite(rest, "rest position"); !status) return status;
    if (Status status = checkGpuLattices(lattice, layers); !status) return status;
    const std::array<int, 3> spans = lattice.spans();
    const int cellCount = spans[0] * spans[1] * spans[2];
    if (int(embedding.cellStart.size()) != cellCount + 1 || embedding.localX.size() != embedding.order.size())
        return Status::error("GPU deformation: the embedding was made for another lattice (" +
                             std::to_string(int(embedding.cellStart.size()) - 1) + " cells, the lattice has " +
                             std::to_string(cellCount) + ")");

    // Per vertex: local coordinates in its cell and the cell, or the identity's mark -1 outside the box.
    std::vector<float> cells(size_t(vertexCount) * 4, 0.0f);
    for (int v = 0; v < vertexCount; ++v) cells[size_t(v) * 4 + 3] = -1.0f;
#pragma omp parallel for schedule(dynamic, 64) if (cellCount > 64)
    for (int cell = 0; cell < cellCount; ++cell)
        for (int e = embedding.cellStart[size_t(cell)]; e < embedding.cellStart[size_t(cell) + 1]; ++e) {
            float* record = cells.data() + size_t(embedding.order[size_t(e)]) * 4;
            record[0] = float(embedding.localX[size_t(e)]);
            record[1] = float(embedding.localY[size_t(e)]);
            record[2] = float(embedding.localZ[size_t(e)]);
            record[3] = float(cell);
        }
    Positions restNormals;
    core::computeVertexNormals(rest, s.triangles, s.adjacency, restNormals);

    const GlFunctions& gl = s.gl;
    s.packVertices(0, vertexCount, rest, restNormals);
    gl.BindBuffer(GL_ARRAY_BUFFER, s.vertexBuffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(s.staging.size() * sizeof(float)), s.staging.data(), GL_DYNAMIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, s.cellBuffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(cells.size() * sizeof(float)), cells.data(), GL_STATIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    gl.BindVertexArray(s.meshVao);
    gl.EnableVertexAttribArray(kAttribLatticeCell);
    gl.BindVertexArray(0);
    s.basisData.clear();
    s.controlData.clear();
    s.uploadLattices(lattice, layers);  // the buffers' stores exist before the textures are attached to them
    gl.BindTexture(GL_TEXTURE_BUFFER, s.basisTexture);
    gl.TexBuffer(GL_TEXTURE_BUFFER, GL_R32F, s.basisBuffer);
    gl.BindTexture(GL_TEXTURE_BUFFER, s.controlTexture);
    gl.TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, s.controlBuffer);
    gl.BindTexture(GL_TEXTURE_BUFFER, 0);
    s.gpuDeformation = true;
    s.lastUpload = {vertexCount, 1, true, s.lastUpload.controlPointsUploaded};
    s.staging.clear();
    s.staging.shrink_to_fit();
    return Status::success();
}

Status Renderer::updateGpuDeformation(const core::Lattice& lattice, const std::vector<const core::Lattice*>& layers) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!s.gpuDeformation) return Status::error("GPU deformation: the GPU path is off (setGpuDeformation first)");
    if (Status status = checkGpuLattices(lattice, layers); !status) return status;
    if (!shapeOf(lattice).sameLattice(s.gpuCage))
        return Status::error("GPU deformation: the lattice is not the one the GPU path was set up with (other counts, "
                             "degrees or box); set it up again");
    s.lastUpload = {};
    s.uploadLattices(lattice, layers);
    return Status::success();
}

Status Renderer::clearGpuDeformation(const Positions& positions) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (positions.rows() != s.positions.rows())
        return Status::error("clearGpuDeformation: " + std::to_string(positions.rows()) + " positions given for a mesh of " +
                             std::to_string(s.positions.rows()) + " vertices");
    if (!s.gpuDeformation) return Status::success();
    if (Status status = checkFinite(positions, "mesh position"); !status) return status;
    s.positions = positions;
    s.uploadAllVertices();
    s.gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    s.leaveGpuPath();
    return Status::success();
}

void Renderer::State::leaveGpuPath() {
    gl.BindVertexArray(meshVao);
    gl.DisableVertexAttribArray(kAttribLatticeCell);
    gl.BindVertexArray(0);
    gpuDeformation = false;
}

bool Renderer::gpuDeformationActive() const { return state_->gpuDeformation; }

void Renderer::State::bindGpuDeformation() const {
    gl.Uniform1i(deformUniforms.control, 0);
    gl.Uniform1i(deformUniforms.basis, 1);
    gl.Uniform1i(deformUniforms.latticeCount, gpuLatticeCount);
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_BUFFER, basisTexture);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_BUFFER, controlTexture);
}

void Renderer::State::unbindGpuDeformation() const {
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_BUFFER, 0);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_BUFFER, 0);
}

Status Renderer::captureGpuDeformation(Positions& positions, Positions& normals) const {
    const State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!s.gpuDeformation) return Status::error("captureGpuDeformation: the GPU path is off");
    const GlFunctions& gl = s.gl;
    const int vertexCount = int(s.positions.rows());
    for (int i = 0; i < 32 && gl.GetError() != GL_NO_ERROR; ++i) {
    }
    GLuint feedback = 0;
    gl.GenBuffers(1, &feedback);
    gl.BindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, feedback);
    gl.BufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(vertexCount) * kFeedbackFloats * GLsizeiptr(sizeof(float)),
                  nullptr, GL_STREAM_READ);
    gl.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, feedback);
    gl.UseProgram(s.deformProgram);
    s.bindGpuDeformation();
    gl.BindVertexArray(s.meshVao);
    gl.Enable(GL_RASTERIZER_DISCARD);
    gl.BeginTransformFeedback(GL_POINTS);
    gl.DrawArrays(GL_POINTS, 0, vertexCount);
    gl.EndTransformFeedback();
    gl.Disable(GL_RASTERIZER_DISCARD);
    std::vector<float> captured(size_t(vertexCount) * kFeedbackFloats);
    gl.GetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(captured.size() * sizeof(float)), captured.data());
    gl.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
    gl.BindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, 0);
    gl.DeleteBuffers(1, &feedback);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    s.unbindGpuDeformation();
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        return Status::error("captureGpuDeformation failed: " + glErrorText(error));
    positions.resize(vertexCount, 3);
    normals.resize(vertexCount, 3);
    for (int v = 0; v < vertexCount; ++v) {
        const float* record = captured.data() + size_t(v) * kFeedbackFloats;
        Eigen::Vector3d normal(record[3], record[4], record[5]);
        if (normal.norm() > 0.0) normal.normalize();
        for (int c = 0; c < 3; ++c) positions(v, c) = double(record[c]) * s.frame.scale + s.frame.origin[c];
        normals.row(v) = normal.transpose();
    }
    return Status::success();
}

void Renderer::finish() const {
    if (state_->ready) state_->gl.Finish();
}

namespace {

// A per-vertex float attribute of the mesh that may be absent: empty values disable the attribute array (the
// shader then reads its constant default).
void uploadOptionalAttribute(const GlFunctions& gl, GLuint vao, GLuint buffer, GLuint attribute,
                             const std::vector<float>& values) {
    // note: the attribute's size (components per vertex) was set once in createObjects.
    gl.BindVertexArray(vao);
    if (values.empty()) {
        gl.DisableVertexAttribArray(attribute);
    } else {
        gl.BindBuffer(GL_ARRAY_BUFFER, buffer);
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(values.size() * sizeof(float)), values.data(), GL_DYNAMIC_DRAW);
        gl.EnableVertexAttribArray(attribute);
        gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    }
    gl.BindVertexArray(0);
}

}  // namespace

Status Renderer::setJacobianField(const std::vector<float>& jacobianDet) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!jacobianDet.empty() && jacobianDet.size() != size_t(s.positions.rows()))
        return Status::error("Jacobian field has " + std::to_string(jacobianDet.size()) + " values for " +
                             std::to_string(s.positions.rows()) + " vertices");
    for (size_t i = 0; i < jacobianDet.size(); ++i)
        if (!std::isfinite(jacobianDet[i]))
            return Status::error("Jacobian field value " + std::to_string(i) + " is not finite");
    uploadOptionalAttribute(s.gl, s.meshVao, s.jacobianBuffer, kAttribJacobian, jacobianDet);
    s.hasJacobian = !jacobianDet.empty();
    return Status::success();
}

Status Renderer::setAffectedWeights(const std::vector<float>& affectedWeight) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!affectedWeight.empty() && affectedWeight.size() != size_t(s.positions.rows()))
        return Status::error("affected-region field has " + std::to_string(affectedWeight.size()) +
                             " values for " + std::to_string(s.positions.rows()) + " vertices");
    for (size_t i = 0; i < affectedWeight.size(); ++i)
        if (std::isnan(affectedWeight[i]))
            return Status::error("affected-region weight " + std::to_string(i) + " is NaN");
    uploadOptionalAttribute(s.gl, s.meshVao, s.affectedBuffer, kAttribAffected, affectedWeight);
    s.hasAffected = !affectedWeight.empty();
    return Status::success();
}

// ---- lattice and constraints ---------------------------------------------------------------------

void Renderer::State::uploadOverlays() {
    std::vector<float> lines, markers;
    Bounds bounds;
    if (buildLatticeInstances(lattice, frame, lines, markers, bounds)) {
        uploadBatch(latticeEdges, lines, kLineFloats);
        uploadLatticeMarkers(markers);
    }
    if (buildConstraintInstances(constraints, frame, lines, markers)) {
        uploadBatch(handleLines, lines, kLineFloats);
        uploadBatch(handlePoints, markers, kMarkerFloats);
    }
}

Status Renderer::setLattice(const LatticeView& lattice) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    // Without a mesh the lattice is the content: its centre and size make the frame.
    LocalFrame frame = s.frame;
    if (s.positions.rows() == 0 && lattice.nu > 0) frame = localFrameOf(boundsOf(lattice.controlPoints));
    std::vector<float> edges, markers;
    Bounds bounds;
    if (Status status = buildLatticeInstances(lattice, frame, edges, markers, bounds); !status) return status;
    s.lattice = lattice;
    s.latticeBounds = bounds;
    if (frame != s.frame) {
        s.frame = frame;
        s.uploadOverlays();
        return Status::success();
    }
    s.uploadBatch(s.latticeEdges, edges, kLineFloats);
    s.uploadLatticeMarkers(markers);
    return Status::success();
}

void Renderer::State::uploadLatticeMarkers(const std::vector<float>& markers) {
    uploadBatch(latticePoints, markers, kMarkerFloats);
    plainMarkerCentres.clear();
    // note: the markers that shrink where they crowd are the unselected ones and the T-junctions (style 1 or 2,
    // buildLatticeInstances); the selection keeps its size.
    for (size_t m = 0; m + kMarkerFloats <= markers.size(); m += kMarkerFloats)
        if (markers[m + 9] > 0.5f) plainMarkerCentres.emplace_back(markers[m], markers[m + 1], markers[m + 2]);
    crowdStale = true;
}

float Renderer::State::markerCrowding(const glm::mat4& viewProjection, int width, int height) const {
    if (!crowdStale && viewProjection == crowdViewProjection && crowdViewport == glm::ivec2(width, height)) return crowdScale;
    std::vector<glm::vec2> pixels;
    pixels.reserve(plainMarkerCentres.size());
    for (const glm::vec3& centre : plainMarkerCentres) {
        const glm::vec4 clip = viewProjection * glm::vec4(centre, 1.0f);
        if (!(clip.w > 0.0f)) continue;
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        if (std::abs(ndc.x) > 1.0f || std::abs(ndc.y) > 1.0f) continue;  // off screen: crowds nothing
        pixels.emplace_back((ndc.x + 1.0f) * 0.5f * float(width), (1.0f - ndc.y) * 0.5f * float(height));
    }
    crowdScale = crowdedMarkerScale(pixels, kControlPointSize * pixelScale);
    crowdViewProjection = viewProjection;
    crowdViewport = glm::ivec2(width, height);
    crowdStale = false;
    return crowdScale;
}

Status Renderer::setConstraints(const ConstraintView& constraints) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    std::vector<float> segments, markers;
    if (Status status = buildConstraintInstances(constraints, s.frame, segments, markers); !status) return status;
    s.constraints = constraints;
    s.uploadBatch(s.handleLines, segments, kLineFloats);
    s.uploadBatch(s.handlePoints, markers, kMarkerFloats);
    return Status::success();
}

Status Renderer::setVertexColors(const std::vector<float>& rgb) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!rgb.empty() && rgb.size() != 3 * size_t(s.positions.rows()))
        return Status::error("vertex colours: " + std::to_string(rgb.size()) + " values for " +
                             std::to_string(s.positions.rows()) + " vertices (3 per vertex)");
    for (size_t i = 0; i < rgb.size(); ++i)
        if (!std::isfinite(rgb[i]))
            return Status::error("vertex colour " + std::to_string(i / 3) + " is not finite");
    uploadOptionalAttribute(s.gl, s.meshVao, s.colorBuffer, kAttribVertexColor, rgb);
    s.hasVertexColors = !rgb.empty();
    return Status::success();
}

bool Renderer::hasVertexColors() const { return state_->hasVertexColors; }

Status Renderer::setScene(const SceneData& scene) {
    if (Status status = setMesh(scene.positions, scene.triangles); !status) return status;
    if (Status status = setVertexColors(scene.vertexColors); !status) return status;
    if (Status status = setJacobianField(scene.jacobianDet); !status) return status;
    if (Status status = setAffectedWeights(scene.affectedWeight); !status) return status;
    if (Status status = setLattice(scene.lattice); !status) return status;
    return setConstraints(scene.constraints);
}

// ---- drawing -------------------------------------------------------------------------------------

void Renderer::State::drawLines(const InstanceBatch& batch, const glm::mat4& viewProjection, int width,
                                int height, float lineWidth, const Rgba& tint, float alphaScale,
                                const glm::vec3& depthFade) const {
    if (batch.count == 0) return;
    gl.UseProgram(lineProgram);
    gl.UniformMatrix4fv(lineUniforms.viewProjection, 1, GL_FALSE, glm::value_ptr(viewProjection));
    gl.Uniform2f(lineUniforms.viewport, float(width), float(height));
    gl.Uniform1f(lineUniforms.width, lineWidth * pixelScale);
    gl.Uniform4f(lineUniforms.tint, tint.r, tint.g, tint.b, tint.a);
    gl.Uniform1f(lineUniforms.alphaScale, alphaScale);
    gl.Uniform3f(lineUniforms.depthFade, depthFade.x, depthFade.y, depthFade.z);
    gl.BindVertexArray(batch.vao);
    gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, batch.count);
}

void Renderer::State::drawPoints(const InstanceBatch& batch, const glm::mat4& viewProjection, int width,
                                 int height, float alphaScale, const glm::vec3& depthFade, float crowd) const {
    if (batch.count == 0) return;
    gl.UseProgram(pointProgram);
    gl.UniformMatrix4fv(pointUniforms.viewProjection, 1, GL_FALSE, glm::value_ptr(viewProjection));
    gl.Uniform2f(pointUniforms.viewport, float(width), float(height));
    gl.Uniform1f(pointUniforms.sizeScale, pixelScale);
    gl.Uniform1f(pointUniforms.crowdScale, crowd);
    gl.Uniform1f(pointUniforms.alphaScale, alphaScale);
    gl.Uniform3f(pointUniforms.depthFade, depthFade.x, depthFade.y, depthFade.z);
    gl.BindVertexArray(batch.vao);
    gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, batch.count);
}

void Renderer::State::drawLattice(const glm::mat4& view, const glm::mat4& projection, int width, int height) const {
    if (latticeEdges.count == 0 && latticePoints.count == 0) return;
    // Depth cue from the nearest to the farthest point of the sphere about the lattice's box, in device depth.
    const glm::vec4 center = view * glm::vec4(glm::vec3(frame.toLocal(latticeBounds.center())), 1.0f);
    const float radius = float(latticeBounds.radius() / frame.scale);
    const auto deviceDepth = [&](float viewZ) {
        const glm::vec4 clip = projection * glm::vec4(0.0f, 0.0f, viewZ, 1.0f);
        return clip.w > 0.0f ? clip.z / clip.w : -1.0f;
    };
    const glm::vec3 fade(deviceDepth(std::min(center.z + radius, 0.0f)), deviceDepth(center.z - radius), kLatticeFarAlpha);
    const glm::mat4 viewProjection = projection * view;
    // Markers that crowd on screen shrink, so the mesh shows between them.
    const float crowd = markerCrowding(viewProjection, width, height);
    // Two passes: the parts behind the mesh faint, the visible parts at full (still translucent) strength.
    gl.DepthFunc(GL_GREATER);
    drawLines(latticeEdges, viewProjection, width, height, kLatticeEdgeWidth, kNoTint, kOccludedAlpha, fade);
    drawPoints(latticePoints, viewProjection, width, height, kOccludedAlpha, fade, crowd);
    gl.DepthFunc(GL_LEQUAL);
    drawLines(latticeEdges, viewProjection, width, height, kLatticeEdgeWidth, kNoTint, 1.0f, fade);
    drawPoints(latticePoints, viewProjection, width, height, 1.0f, fade, crowd);
}

void Renderer::State::drawJacobianLegend(const DrawOptions& options, int width, int height) const {
    const std::vector<float> vertices = buildJacobianLegend(width, height, pixelScale, options.uiInsetBottom, kJacobianRange);
    if (vertices.empty()) return;
    gl.Disable(GL_DEPTH_TEST);
    gl.UseProgram(overlayProgram);
    gl.Uniform2f(overlayUniforms.viewport, float(width), float(height));
    gl.Uniform1f(overlayUniforms.jacobianRange, kJacobianRange);
    gl.BindVertexArray(overlayVao);
    gl.BindBuffer(GL_ARRAY_BUFFER, overlayBuffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STREAM_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size() / kOverlayFloats));
}

Status Renderer::draw(const Camera& camera, const DrawOptions& options, int width, int height) const {
    const State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (width <= 0 || height <= 0)
        return Status::error("viewport size " + std::to_string(width) + " x " + std::to_string(height) +
                             " is empty: width and height must be at least 1");
    const GlFunctions& gl = s.gl;
    const double aspect = double(width) / double(height);
    // In the GPU's local frame, made in double and only then rounded to float (camera.h).
    const glm::mat4 view(camera.view(s.frame));
    const glm::mat4 projection(camera.projection(aspect, s.frame));
    const glm::mat4 viewProjection = projection * view;

    for (int i = 0; i < 32 && gl.GetError() != GL_NO_ERROR; ++i) {
    }  // only errors raised below are reported
    gl.Viewport(0, 0, width, height);
    gl.Disable(GL_SCISSOR_TEST);
    gl.Disable(GL_STENCIL_TEST);
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_BLEND);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    gl.ClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    gl.ClearDepth(1.0);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    if (options.background) {
        gl.Disable(GL_DEPTH_TEST);
        gl.UseProgram(s.backgroundProgram);
        gl.Uniform3f(s.backgroundUniforms.topColor, kBackgroundTop[0], kBackgroundTop[1], kBackgroundTop[2]);
        gl.Uniform3f(s.backgroundUniforms.bottomColor, kBackgroundBottom[0], kBackgroundBottom[1],
                     kBackgroundBottom[2]);
        gl.BindVertexArray(s.emptyVao);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
    }

    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    // The proxy while things move (when the mesh has one): the same vertices, fewer triangles.
    const bool useProxy = options.proxy && s.proxyIndexCount > 0;
    const GLsizei indexCount = useProxy ? s.proxyIndexCount : GLsizei(s.triangles.size());
    const void* firstIndex = reinterpret_cast<const void*>(useProxy ? s.triangles.size() * sizeof(int) : 0);
    s.lastDrawnTriangles = indexCount / 3;
    if (indexCount > 0) {
        // The GPU path deforms the rest mesh in its vertex shader; both programs share the mesh uniforms.
        const MeshUniforms& uniforms = s.gpuDeformation ? s.deformMeshUniforms : s.meshUniforms;
        gl.UseProgram(s.gpuDeformation ? s.deformProgram : s.meshProgram);
        if (s.gpuDeformation) s.bindGpuDeformation();
        gl.UniformMatrix4fv(uniforms.view, 1, GL_FALSE, glm::value_ptr(view));
        gl.UniformMatrix4fv(uniforms.projection, 1, GL_FALSE, glm::value_ptr(projection));
        gl.Uniform1i(uniforms.mode, 0);
        gl.Uniform1i(uniforms.showJacobian, options.jacobian ? 1 : 0);
        gl.Uniform1i(uniforms.showAffected, options.affected ? 1 : 0);
        gl.Uniform1i(uniforms.showVertexColors, options.vertexColors && s.hasVertexColors ? 1 : 0);
        gl.Uniform1f(uniforms.jacobianRange, kJacobianRange);
        // Absent fields read as constants: det J = 1 (unchanged), weight 0 (unaffected).
        if (!s.hasJacobian) gl.VertexAttrib1f(kAttribJacobian, 1.0f);
        if (!s.hasAffected) gl.VertexAttrib1f(kAttribAffected, 0.0f);
        gl.BindVertexArray(s.meshVao);
        if (options.wireframe) {
            // Push the surface back a little so its own edges pass the depth test on top of it.
            gl.Enable(GL_POLYGON_OFFSET_FILL);
            gl.PolygonOffset(1.0f, 1.0f);
        }
        gl.DrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, firstIndex);
        gl.Disable(GL_POLYGON_OFFSET_FILL);
        if (options.wireframe) {
            gl.PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
            gl.Enable(GL_BLEND);
            gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            gl.DepthFunc(GL_LEQUAL);
            gl.DepthMask(GL_FALSE);
            gl.Uniform1i(uniforms.mode, 1);
            gl.Uniform4f(uniforms.wireColor, kWireColor.r, kWireColor.g, kWireColor.b, kWireColor.a);
            gl.DrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, firstIndex);
            gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
            gl.DepthMask(GL_TRUE);
            gl.DepthFunc(GL_LESS);
        }
        if (s.gpuDeformation) s.unbindGpuDeformation();
    }

    // Overlays blend over the surface and never write depth.
    gl.Enable(GL_BLEND);
    gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl.DepthMask(GL_FALSE);
    if (options.lattice) s.drawLattice(view, projection, width, height);
    if (options.constraints) {
        // Handles are what the user is manipulating: always on top (Hu et al. 2001, Fig. 1 style).
        gl.Disable(GL_DEPTH_TEST);
        s.drawLines(s.handleLines, viewProjection, width, height, kHandleShadowWidth, kHandleShadow, 1.0f);
        s.drawLines(s.handleLines, viewProjection, width, height, kHandleLineWidth, kNoTint, 1.0f);
        s.drawPoints(s.handlePoints, viewProjection, width, height, 1.0f);
    }
    if (options.jacobian && s.hasJacobian && indexCount > 0) s.drawJacobianLegend(options, width, height);

    gl.Disable(GL_BLEND);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    gl.DepthMask(GL_TRUE);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        return Status::error("drawing failed: " + glErrorText(error));
    return Status::success();
}

void Renderer::setMeshProxyOptions(const MeshProxyOptions& options) { state_->proxyOptions = options; }
void Renderer::setPixelScale(float scale) {
    state_->pixelScale = scale > 0.0f ? scale : 1.0f;
    state_->crowdStale = true;
}
float Renderer::pixelScale() const { return state_->pixelScale; }
float Renderer::lastMarkerCrowding() const { return state_->crowdScale; }
int Renderer::vertexCount() const { return int(state_->positions.rows()); }
int Renderer::triangleCount() const { return int(state_->triangles.rows()); }
int Renderer::proxyTriangleCount() const { return int(state_->proxyIndexCount / 3); }
int Renderer::lastDrawnTriangles() const { return state_->lastDrawnTriangles; }
Bounds Renderer::meshBounds() const { return boundsOf(state_->positions); }
Bounds Renderer::latticeBounds() const { return state_->latticeBounds; }
LocalFrame Renderer::localFrame() const { return state_->frame; }
const Positions& Renderer::positions() const { return state_->positions; }
const Positions& Renderer::normals() const { return state_->normals; }
UploadStats Renderer::lastUpload() const { return state_->lastUpload; }

}  // namespace sculpt::render
