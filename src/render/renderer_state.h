// The renderer's GL state (renderer.h keeps it behind a pointer), shared by its source files: renderer.cpp
// (the mesh, the overlays, drawing) and renderer_gpu_deformation.cpp (the deformation in the vertex shader).
// Internal to src/render: nothing outside includes it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <glm/glm.hpp>

#include "core/deform/vertex_normals.h"
#include "render/gl_functions.h"
#include "render/mesh_proxy.h"
#include "render/palette.h"
#include "render/renderer.h"

namespace sculpt::render {


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

inline std::string glErrorText(GLenum error) {
    switch (error) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        default: return "GL error " + std::to_string(error);
    }
}

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

}  // namespace sculpt::render
