// Benchmarks of the brush (issue "Sculpting as a sculptor expects", point 5): one JSON line per case
// (bench_support.h).
#pragma once

#include <string>
#include <vector>

namespace sculpt::bench {

// Runs the brush cases whose name contains one of `filters` (all for an empty list):
//   strokes_real    100 random strokes on each of three of CGAL's meshes (elephant, camel, armadillo): radius
//                   3-15% of the diagonal, pulls of 0.1-3 radii along the normal, a tangent and inward, with and
//                   without symmetry, conic and exact; the share applied in full, stopped short and refused, the
//                   profile RMS, the ms per move, and the crossing pairs by the independent exact test
//                   (tests/core/mesh_fixtures.h). SCULPT_BENCH_SUBDIVIDE=k first splits every triangle in 4, k
//                   times; SCULPT_BENCH_VERBOSE=1 names each stroke that stops or adds pairs.
//   brush_move_1m   one brush move on a 1M-vertex sphere (radius 5% of the diagonal, with the test and the
//                   triangle check)
//   stroke_coarse   window-like strokes on the coarse elephant: the point grabbed inside a large triangle pulled to
//                   3 radii in 20 moves; ms per move and the vertices split in under the pull
//   stroke_past_stop  window-like long strokes on CGAL's camel dragged on to twice their pull: ms per move past
//                   where a stroke stops (median, max) and of the move that first stopped
void runBrushBenchmarks(const std::vector<std::string>& filters = {});

}  // namespace sculpt::bench
