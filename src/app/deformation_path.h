// Which path deforms the mesh on screen (issue: big meshes stay interactive):
//   - CPU: the engine's positions, then the normals around the moved vertices and their upload
//     (Renderer::updatePositions);
//   - GPU: the vertex shader evaluates the box lattice's deformation from the rest mesh, and per frame only the
//     control displacements go up (Renderer::setGpuDeformation, Chua & Neumann 2000).
// Which is faster depends on the machine: on a real GPU the vertex shader is nearly free and the CPU's normals
// and upload of a big mesh are not; on a software rasteriser (llvmpipe) every draw pays for the shader. So the
// window measures frames of both while the user drags a big mesh and keeps the faster one. No GL here: the
// caller times its frames and reports them.
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
    // Frames measured per path before deciding (the first frame after each switch is not counted: it uploads
    // the whole mesh).
    static constexpr int kFramesPerPath = 5;

    // A new mesh (or a new context): decide again. vertexCount >= 0.
    void reset(int vertexCount);
    // Whether the decision made for the last reset's mesh holds for a mesh of vertexCount (both small, or both
    // measured): a refinement need not measure again.
    bool decidedFor(int vertexCount) const { return (vertexCount >= minVertices_) == (vertexCount_ >= minVertices_); }
    // The smallest mesh that is measured (tests lower it); takes effect at the next reset.
    void setMinVertices(int vertices) { minVertices_ = vertices; }
    // Takes `path` and stops measuring until the next reset (tests; a user's explicit choice).
    void force(DeformationPath path) {
        path_ = path;
        deciding_ = false;
        forced_ = true;
    }
    // The path the next frame takes when the GPU can take the lattice at all.
    DeformationPath path() const { return path_; }
    // Still measuring: the caller should time its frames (update + draw, waited for) and report them.
    bool deciding() const { return deciding_; }
    // One measured frame (milliseconds, finite and >= 0; others are ignored) on `path`, a frame in which the
    // mesh moved. Switches paths and decides as frames come in.
    void addFrame(DeformationPath path, double milliseconds);
    // Median of the frames counted on `path`, or a negative value before any.
    double medianMs(DeformationPath path) const;
    // For the stats panel: the path in use and why, e.g. "GPU (vertex shader), 3.1 vs 19.8 ms a frame".
    std::string describe() const;

private:
    int minVertices_ = kDefaultMinVertices;
    int vertexCount_ = 0;
    DeformationPath path_ = DeformationPath::Cpu;
    bool deciding_ = false;
    bool skipNext_ = true;  // the first frame on a path pays the switch
    bool forced_ = false;
    std::array<std::vector<double>, 2> frames_;
};

}  // namespace sculpt::app
