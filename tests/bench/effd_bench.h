// Benchmarks of lattices of any shape (Coquillart 1990, EFFD): one JSON line per case (bench_support.h).
#pragma once

#include <string>
#include <vector>

namespace sculpt::bench {

// Runs the EFFD cases whose name contains one of `filters` (all for an empty list), on 1M points filling a
// cylindrical lattice of 2 x 12 x 1 chunks (degree 2 radial and axial, rational quadratic arcs):
//   effd_freeze_1m     freezing every point (parameters by Newton per chunk, 3.3), both cores
//   effd_eval_1m       evaluating all of them after a displacement of every control point (the kernel),
//                      with box_eval_1m: the same points in a box lattice with the same control point count
//   effd_drag_step     one mouse move of an interactive drag on the frozen cylinder (solve, test, update)
void runEffdBenchmarks(const std::vector<std::string>& filters = {});

}  // namespace sculpt::bench
