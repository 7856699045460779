// Renderer benchmarks for the sculpt_bench executable: one JSON line per case on `out`.
// Needs a GL context: uses OSMesa/EGL offscreen (SCULPT_GL_BACKEND=osmesa|egl|auto, default auto).
#pragma once

#include <ostream>

namespace sculpt::render {

// Cases (1280 x 800, 4x MSAA, median of >= 10 frames, each ended with glFinish):
//   render_100k, render_1m   a lit sphere of 100k / 1M triangles covering about half the picture
//   upload_1m                updatePositions with all 1M vertices changed (normals + whole-buffer upload)
//   upload_1m_local          updatePositions with a 2% patch changed (sparse normals + ranged upload)
// A case that cannot run (no GL) prints {"case": ..., "error": "..."} instead.
void runRenderBenchmarks(std::ostream& out);
//   gpu_drag_1m, gpu_drag_10m  frames per second of a global drag (every vertex moves), CPU path against the
//                              vertex-shader path (Renderer::setGpuDeformation); the 10M case only when asked.
void runGpuDragBenchmarks(std::ostream& out, bool tenMillion);

}  // namespace sculpt::render
