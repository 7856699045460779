// A real scan made large: CGAL's armadillo (26k vertices) refined by CGAL's Loop subdivision, for the triangle check
// at a million-vertex scale on a scan's own triangles.
#pragma once

#include <string>

#include "core/mesh_types.h"

namespace sculpt::bench {

// Loads data/meshes/NAME from CGAL's data and applies `iterations` steps of Loop subdivision (each about 4x the
// vertices). false with the reason in `error` when the mesh is missing or not a closed triangle manifold.
bool loopSubdividedCgalMesh(const std::string& name, int iterations, Positions& positions, Triangles& triangles,
                            std::string& error);

}  // namespace sculpt::bench
