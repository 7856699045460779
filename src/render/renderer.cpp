#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <omp.h>

#include <glm/gtc/type_ptr.hpp>

#include "core/deform/vertex_normals.h"
#include "render/gl_functions.h"
#include "render/legend.h"
#include "render/overlay_geometry.h"
#include "render/palette.h"
#include "render/shader_program.h"
#include "render/renderer_state.h"

namespace sculpt::render {

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
