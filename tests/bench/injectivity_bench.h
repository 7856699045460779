// Benchmarks of the injectivity tests (Gain & Dodgson 2001, sections 6-7): one JSON line per case, as the
// other cases of sculpt_bench (bench_support.h).
#pragma once

#include <string>
#include <vector>

namespace sculpt::bench {

// Runs the injectivity cases whose name contains one of `filters` (all of them for an empty list):
//   inject_conic_16        conic test, whole 16^3 cubic lattice after a realistic local deformation
//   inject_conic_16_cells  the same, only the cells influenced by the moved control points (per-drag path)
//   inject_conic_16_dense  conic test, every control point of the 16^3 lattice moved (worst case)
//   inject_exact_8         exact test, whole 8^3 cubic lattice after a realistic deformation
//   inject_exact_8_fold    exact test, 8^3 lattice after drags long enough to fold it (finding the fold)
//   inject_exact_8_dense   exact test, every control point of the 8^3 lattice moved
// Each prints the median of >= 10 runs (after a warm-up), the minimum and the verdict.
void runInjectivityBenchmarks(const std::vector<std::string>& filters = {});

}  // namespace sculpt::bench
