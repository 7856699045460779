// Small helpers shared by the files that implement Session and its concept classes (session*.cpp, stroke*.cpp,
// tool_library.cpp, tspline_*.cpp, refiner.cpp); not part of the engine's interface.
#pragma once

#include <chrono>
#include <string>

#include <Eigen/Core>

#include "core/deform/direct_manipulation.h"
#include "core/session/operation.h"

namespace sculpt::core::detail {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start);
// "(x, y, z)" with %g.
std::string vectorText(const Eigen::Vector3d& v);
// "12.5%" (one decimal) for a fraction in [0, 1].
std::string percentText(double fraction);
// Adds b into a (sorted unions of control point ids).
void mergeDelta(ControlDelta& a, const ControlDelta& b);

// An operation stopped or refused by a step that failed: its cause (OpReport::refusedBy) and what the test found
// (OpReport::failureWords; drag: the words for a drag, "mesh" rather than "lattice").
inline void noteFailure(OpReport& report, const StepFailure& failure, bool drag) {
    report.refusedBy = stepFailureCauseName(failure.cause);
    report.failureWords = stepFailureWords(failure, drag);
}

}  // namespace sculpt::core::detail
