// Which path deforms the mesh on screen (issue: big meshes stay interactive):
//   - CPU: the engine's positions, then the normals around the moved vertices and their upload
//     (Renderer::updatePositions);
//   - GPU: the vertex shader evaluates the box lattices' deformation from the rest mesh, and per frame only the
//     control displacements go up (Renderer::setGpuDeformation, Chua & Neumann 2000).
// Which is faster depends on the machine and on the frame: on a real GPU the vertex shader is nearly free and the
// CPU's normals and upload of a big mesh are not; on a software rasteriser (llvmpipe) every vertex the shader
// deforms costs CPU time, which pays off while a drag draws the mesh's decimated proxy but not for a still frame
// of the whole mesh. So the window measures both kinds of frame on both paths and chooses for each:
//   - drag frames (update and draw while the mesh moves in a drag): the first drag on a big mesh runs three
//     on the GPU path, then three on the CPU path (each path's first frame pays the switch and is not counted);
//     the shorter median wins;
//   - still frames (the whole mesh drawn, nothing moving): one on each path, the first at rest on it. The CPU
//     path is the rest path until the GPU's still frame is measured no slower than 1.25 times the CPU's.
// No GL here: the caller times its frames (to the end of the draw, glFinish included) and reports them.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace sculpt::app {

enum class DeformationPath { Cpu, Gpu };

class DeformationPathChooser {
public:
    // Meshes smaller than this stay on the CPU path without measuring (either path is a fraction of a
    // millisecond there).
    static constexpr int kDefaultMinVertices = 100000;
    // Drag frames measured per path before deciding (few: on a slow machine a drag has few frames, and a user
    // should not have to drag three times before the choice is made).
    static constexpr int kFramesPerPath = 3;

    // A new mesh (or a new context): decide again. vertexCount >= 0.
    void reset(int vertexCount);
    // Whether the decision made for the last reset's mesh holds for a mesh of vertexCount (both small, or both
    // measured): a refinement need not measure again.
    bool decidedFor(int vertexCount) const { return (vertexCount >= minVertices_) == (vertexCount_ >= minVertices_); }
    // The last reset's mesh is big enough to be measured (smaller ones stay on the CPU).
    bool measuresThisMesh() const { return measured(); }
    // The smallest mesh that is measured (tests lower it); takes effect at the next reset.
    void setMinVertices(int vertices) { minVertices_ = vertices; }
    // Takes `path` for every frame and stops measuring until the next reset (tests; a user's explicit choice).
    void force(DeformationPath path);

    // The path for a frame in which the mesh moves in a drag: the one being measured, then the faster.
    DeformationPath dragPath() const;
    // The path for every other frame (still, or the view moving).
    DeformationPath restPath() const;
    // Drag frames are still being measured: the caller times the frames in which the dragged mesh moved.
    bool deciding() const { return deciding_; }
    // One drag frame (milliseconds, finite and >= 0; others are ignored) on `path`. Switches the measured path
    // and decides as frames come in.
    void addDragFrame(DeformationPath path, double milliseconds);
    // Whether a still frame on `path` should be timed (the first one at rest on each path, big meshes only).
    bool wantsStillFrame(DeformationPath path) const;
    void addStillFrame(DeformationPath path, double milliseconds);
    // Median of the drag frames counted on `path`, the still frame's time; negative before any.
    double medianMs(DeformationPath path) const;
    double stillMs(DeformationPath path) const { return still_[slot(path)]; }
    // For the stats panel: a short label of the path this frame takes ("CPU", "GPU", "GPU (timing)" in a drag
    // being timed, "GPU drag, CPU rest") and the whole story for its tooltip.
    std::string label(bool dragging) const;
    std::string describe() const;

private:
    static size_t slot(DeformationPath path) { return path == DeformationPath::Gpu ? 1 : 0; }
    bool measured() const { return vertexCount_ > 0 && vertexCount_ >= minVertices_; }
    int minVertices_ = kDefaultMinVertices;
    int vertexCount_ = 0;
    DeformationPath measuring_ = DeformationPath::Gpu;  // while deciding
    DeformationPath decided_ = DeformationPath::Cpu;    // the drag frames' winner
    bool deciding_ = false;
    bool forced_ = false;
    bool skipNext_ = true;  // the first drag frame on a path pays the switch
    bool started_ = false;  // a drag frame has come in since the reset
    std::array<std::vector<double>, 2> frames_;
    std::array<double, 2> still_{-1.0, -1.0};
};

}  // namespace sculpt::app
