// Plain mesh arrays shared by every layer: #V x 3 positions, #T x 3 triangle indices.
// Row-major so a row is one contiguous xyz triple (uploads and scatters stay simple).
#pragma once

#include <Eigen/Core>

namespace sculpt {

using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace sculpt
