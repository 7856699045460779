// Small helpers shared by the files that implement Session (session.cpp, session_drag.cpp,
// session_layers.cpp); not part of the engine's interface.
#pragma once

#include <chrono>
#include <string>

#include <Eigen/Core>

#include "core/deform/direct_manipulation.h"

namespace sculpt::core::detail {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start);
// "(x, y, z)" with %g.
std::string vectorText(const Eigen::Vector3d& v);
// "12.5%" (one decimal) for a fraction in [0, 1].
std::string percentText(double fraction);
// Adds b into a (sorted unions of control point ids).
void mergeDelta(ControlDelta& a, const ControlDelta& b);

}  // namespace sculpt::core::detail
