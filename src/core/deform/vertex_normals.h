// Area-weighted vertex normals of a triangle mesh, full and sparse (only around changed vertices).
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_types.h"

namespace sculpt::core {

// Vertex -> incident triangles, in CSR form. Built once per topology.
struct VertexTriangles {
    std::vector<int> offsets;    // #V + 1
    std::vector<int> triangles;  // offsets[v] .. offsets[v+1]-1 are the triangles around v
    // Scratch for updateVertexNormals (one byte per vertex, all zero between calls), kept here so a sparse
    // update neither sorts nor allocates. One update at a time per adjacency.
    mutable std::vector<std::uint8_t> stale;
    // Scratch for computeVertexNormals with this adjacency: 3 per triangle, kept so that a full update of a
    // big mesh does not fault in fresh pages each time. One computation at a time per adjacency.
    mutable std::vector<double> faceNormals;
};

VertexTriangles buildVertexTriangles(int vertexCount, const Triangles& triangles);

// normals: resized to #V x 3. Each normal is the normalised sum of the (area-weighted) face normals
// around the vertex; a vertex with no non-degenerate incident triangle gets (0,0,1), never NaN.
void computeVertexNormals(const Positions& positions, const Triangles& triangles, Positions& normals);

// The same with the mesh's adjacency already built (buildVertexTriangles of these triangles), for repeated
// full updates (the renderer's, after a global change): each face normal is computed once into the
// adjacency's scratch, then summed per vertex in parallel. The values equal the overload above's bit for bit.
void computeVertexNormals(const Positions& positions, const Triangles& triangles, const VertexTriangles& adjacency,
                          Positions& normals);

// Recomputes normals only for the vertices that share a triangle with a vertex in changedVertices
// (positions of those moved). normals must already be #V x 3. Parallel over vertices.
void updateVertexNormals(const Positions& positions, const Triangles& triangles, const VertexTriangles& adjacency,
                         const std::vector<int>& changedVertices, Positions& normals);

}  // namespace sculpt::core
