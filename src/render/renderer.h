// The OpenGL 3.3 core renderer: shaded mesh (+ wireframe, det J and affected-region overlays), control
// lattice, constraint handles, background. It draws into whatever framebuffer is bound in the current
// context and knows nothing of windows; the window (GLFW) and the offscreen contexts (OSMesa, EGL) both
// use it. All GL calls go through a GlFunctions table loaded from the context (see gl_functions.h).
//
// Lifetime: init() and every other member that touches GL need the context current. GL objects are freed
// by release() (also with the context current); the destructor makes no GL calls.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/volume/embedding.h"
#include "core/volume/lattice.h"
#include "core/mesh_types.h"
#include "core/status.h"
#include "render/camera.h"
#include "render/gl_proc.h"
#include "render/mesh_proxy.h"
#include "render/scene.h"

namespace sculpt::render {

struct GlFunctions;

// Background gradient, sRGB in [0, 1], interpolated in sRGB from the top row to the bottom row.
inline constexpr std::array<float, 3> kBackgroundTop = {0.345f, 0.365f, 0.400f};
inline constexpr std::array<float, 3> kBackgroundBottom = {0.125f, 0.133f, 0.149f};

// What the last setMesh / updatePositions sent to the GPU (for tests and benchmarks).
struct UploadStats {
    int verticesUploaded = 0;  // vertex records (position + normal) written
    int ranges = 0;            // glBufferSubData calls for the vertex buffer
    bool fullUpload = false;   // the whole buffer was rewritten
    int controlPointsUploaded = 0;  // control displacements sent for the deformation on the GPU
};

class Renderer {
public:
    Renderer();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Loads GL entry points with getProc (glfwGetProcAddress, OSMesaGetProcAddress, eglGetProcAddress),
    // checks for GL >= 3.3 and builds the shader programs. Fails with the driver's log on a shader error.
    Status init(GlGetProc getProc);
    Status init(const GlFunctions& gl);
    void release();  // frees all GL objects; init() may be called again
    bool initialized() const;

    // Replaces the mesh. positions #V x 3 (all finite), triangles #F x 3 (indices in [0, #V)).
    // Computes area-weighted vertex normals and uploads everything, with the decimated proxy of a large mesh
    // (mesh_proxy.h: about 0.5 s for 500k triangles). Clears the per-vertex fields.
    // An empty mesh (#V = 0) is valid and draws nothing. On failure the previous mesh stays.
    Status setMesh(const Positions& positions, const Triangles& triangles);

    // On the GPU path (setGpuDeformation) this fails: the vertex buffer holds rest positions there.
    // positions: the mesh's full current #V x 3 array, but only the rows listed in changedVertices are
    // read (their values must be finite; indices in [0, #V), duplicates allowed). Recomputes the normals
    // around them (core::updateVertexNormals) and re-uploads only the changed vertex ranges, or the whole
    // buffer when more than a quarter of the vertices changed. On failure nothing changes.
    Status updatePositions(const Positions& positions, const std::vector<int>& changedVertices);

    // ---- the deformation on the GPU (vertex-shader FFD, Chua & Neumann 2000) ----
    // Instead of deformed positions, the vertex shader evaluates the session's map x = L_k(...L_1(C(X0))) and
    // the normal cof(J) n0 (shaders/mesh.vert): the cage C(X0) = X0 + sum R_ijk(t) delta_ijk (Hu et al. 2001,
    // eq. 1-2) from the rest positions and each vertex's cell and local coordinates (uploaded once), then each
    // layer L (core/session/session.h: a brush region, a subdivision step) y -> y + sum R(t(y)) delta with t(y) its box's
    // linear map, as LatticeStack::pushThroughLayers does. Per frame only the control displacements go up (a few KB).
    // Empty string when the GPU can evaluate these lattices: box lattices (no volume), polynomial or rational,
    // the cage and up to 1024 layers. Otherwise why not (the CPU path, updatePositions, takes every kind).
    static std::string gpuDeformationProblem(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers = {});
    // Switches the mesh to the GPU path: rest #V x 3 (the mesh's vertex count, finite) are the positions the
    // embedding was made of (core::embedVertices(lattice, rest)), lattice the cage with its current
    // displacements, layers those after it in order (each non-null). Computes the rest normals (area-weighted)
    // and uploads rest positions, rest normals, cells and local coordinates: a full upload, once per rest mesh.
    // Fails (nothing changes) on lattices the GPU path does not take (gpuDeformationProblem), an embedding of
    // another lattice or vertex count, a wrong row count, or a non-finite value or empty box, naming it.
    Status setGpuDeformation(const core::Lattice& lattice, const core::Embedding& embedding, const Positions& rest,
                             const std::vector<const core::Lattice*>& layers = {});
    // Per frame on the GPU path: the lattices' current displacements and weights (#P x 4 floats each, only the
    // range that changed; the lattice table and bases too when the layers changed). The cage must have the shape setGpuDeformation was given (counts,
    // degrees, box); fails otherwise, on a bad value, or when the GPU path is off (nothing changes).
    Status updateGpuDeformation(const core::Lattice& lattice, const std::vector<const core::Lattice*>& layers = {});
    // Back to the CPU path with the current positions (#V x 3, finite): recomputes every normal and rewrites
    // the vertex buffer, as updatePositions of every vertex does. Fails (nothing changes) on a wrong row count
    // or a non-finite position. A no-op success when the GPU path is off and positions are those already kept.
    Status clearGpuDeformation(const Positions& positions);
    bool gpuDeformationActive() const;
    // What the vertex shader computes on the GPU path, read back by transform feedback: positions and unit
    // normals, #V x 3 each, world units. For tests and benchmarks (it stalls the pipeline). Fails when the GPU
    // path is off.
    Status captureGpuDeformation(Positions& positions, Positions& normals) const;
    // Waits for the GPU to finish every command given so far (glFinish): for timing a frame.
    void finish() const;

    // Per-vertex fields: #V values, or empty to clear. det J must not be NaN (any value <= 0 is a
    // fold-over); weights are clamped to [0, 1] when drawn.
    Status setJacobianField(const std::vector<float>& jacobianDet);
    Status setAffectedWeights(const std::vector<float>& affectedWeight);

    // The mesh's own colours (a scan's, from a PLY, glTF or OBJ file), drawn as its albedo under the same
    // lighting where DrawOptions::vertexColors asks: rgb #V x 3 values (sRGB in [0, 1], values outside are
    // clamped when drawn), or empty to clear. Fails on a wrong count or a non-finite value (nothing changes).
    // setMesh clears them.
    Status setVertexColors(const std::vector<float>& rgb);
    bool hasVertexColors() const;

    // nu = 0 clears. Otherwise nu, nv, nw >= 1, controlPoints (nu*nv*nw) x 3 finite, selected / pinned
    // empty or one per control point.
    Status setLattice(const LatticeView& lattice);
    // sources and targets #C x 3 each (finite); C = 0 clears.
    Status setConstraints(const ConstraintView& constraints);

    // All of the above from one struct; on failure the renderer keeps its previous state for the part
    // that failed and every part before it has been replaced.
    Status setScene(const SceneData& scene);

    // Draws into the currently bound framebuffer, viewport (0, 0, width, height): clears colour and depth,
    // then background, mesh, wireframe, lattice, constraints, and with the det J overlay its legend. Leaves VAO 0, program 0, polygon mode FILL,
    // blending off, depth test on and depth writes on. Fails (drawing nothing) on a non-positive size or
    // before init(); reports a GL error raised while drawing.
    Status draw(const Camera& camera, const DrawOptions& options, int width, int height) const;

    // How the next setMesh builds the decimated proxy (mesh_proxy.h); minTriangles = INT_MAX: never (the
    // benchmark's comparison).
    void setMeshProxyOptions(const MeshProxyOptions& options);

    // Screen-space sizes (line widths, marker diameters) are multiplied by this; 2 for a HiDPI window.
    void setPixelScale(float scale);
    float pixelScale() const;
    // The factor the last draw() that drew the lattice shrank its unselected control-point markers by, where
    // they crowd on screen (crowdedMarkerScale, overlay_geometry.h): 1 when they do not.
    float lastMarkerCrowding() const;

    int vertexCount() const;
    int triangleCount() const;
    // Triangles of the decimated proxy drawn while things move (mesh_proxy.h), 0 when the mesh has none.
    int proxyTriangleCount() const;
    // Mesh triangles the last draw() drew: triangleCount(), or proxyTriangleCount() with DrawOptions::proxy.
    int lastDrawnTriangles() const;
    Bounds meshBounds() const;     // of the current positions
    Bounds latticeBounds() const;  // of the control points (empty without a lattice)
    // The frame the GPU coordinates are in (camera.h): set by setMesh from the mesh's centre and radius, by
    // setLattice from the lattice's while the mesh is empty; the identity before either. Lattice and
    // constraints are re-expressed when it changes, so callers never see it except in tests.
    LocalFrame localFrame() const;
    // Positions as last given by setMesh / updatePositions / clearGpuDeformation (not the GPU path's frames).
    const Positions& positions() const;  // current positions, as uploaded
    const Positions& normals() const;    // current vertex normals, as uploaded
    UploadStats lastUpload() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace sculpt::render
