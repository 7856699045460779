// Benchmarks of the interactive window (issue item 10) for the sculpt_bench executable: one JSON line per
// case, as the other cases (bench_support.h). Not a test: nothing here asserts a time.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace sculpt::bench {

// Runs the window cases whose name contains one of `filters` (all of them for an empty list):
//   window_drag_100k         SculptApp on a 100k-triangle sphere in a 1280 x 800 offscreen EGL window with the
//                            Dear ImGui UI, no MSAA (as the window on a software rasterizer): a left-press on
//                            the mesh, then mouse moves, each followed by a full frame (scene + UI) and
//                            glFinish. Frames per second while dragging and the split per frame: engine
//                            (onMouseMove: Session::updateDrag + noteSessionMoved), GPU update (sparse
//                            position upload + overlays), draw calls, and the wait in glFinish (llvmpipe
//                            rasterizes there).
//   window_drag_1m_engine    the same input on a 1M-vertex sphere, default 8^3 lattice, without drawing: the
//                            engine time per mouse move, and (where EGL exists) the sparse position upload
//                            of the vertices it moved, as the next frame's syncGpu does.
//   window_drag_1m_engine_16 the same on a 16^3 lattice (a more local drag).
//   window_idle              the real program under Xvfb with no input, on the default mesh and CGAL's
//                            armadillo: the share of one core the process uses and the frames it draws over
//                            10 s once the mesh is shown (SCULPT_WINDOW_IDLE_SECONDS; target under 2%).
// Without EGL at run time the frame case prints {"case": ..., "error": ...} and the engine cases skip the upload.
void runWindowBenchmarks(std::ostream& out, const std::vector<std::string>& filters = {});

}  // namespace sculpt::bench
