// Benchmarks of weighted T-spline volumes (Song & Yang 2005, w-TFFD): one JSON line per case (bench_support.h).
#pragma once

#include <string>
#include <vector>

namespace sculpt::bench {

// Runs the T-spline cases whose name contains one of `filters` (all for an empty list):
//   tspline_counts_*       control points of the octree T-lattice against the regular lattice of the same
//                          finest cells (Table 1's comparison) at depths 3, 4, 5, on the default mesh and on
//                          1M points of a bumpy sphere (time: building the volume)
//   tspline_rest_check_d4, _d5   the proof that the rest volume does not fold (checkTSplineRestVolume, run by
//                          every TSplineVolume::make) on the default mesh's depth-4 and depth-5 octree volumes
//   tspline_param_15k_d5   parametrization (freezing) of 15k surface points in their depth-5 octree volume
//   tspline_param_1m_d4    the same for 1M points at depth 4
//   tspline_eval_1m        evaluating the 1M points after a displacement of every control point
//   tspline_drag_step      one mouse move of an interactive drag on a 100k-point surface in a depth-4 volume
void runTSplineBenchmarks(const std::vector<std::string>& filters = {});

}  // namespace sculpt::bench
