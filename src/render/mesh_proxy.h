// A decimated stand-in for a large mesh, drawn while the camera moves or a drag is in progress, when a
// software rasterizer cannot draw every triangle at an interactive rate (llvmpipe: about 100k triangles at
// 30 fps at 1280 x 800). The full mesh comes back as soon as the motion stops.
//
// The proxy is an index buffer over the mesh's own vertices (meshoptimizer's simplifier keeps a subset of
// them and re-triangulates around the ones it drops), so it shares the full mesh's vertex buffer: every
// position and normal update reaches it for free and it deforms exactly as the mesh does, at the kept vertices.
#pragma once

#include "core/mesh_types.h"

namespace sculpt::render {

struct MeshProxyOptions {
    int minTriangles = 100000;    // meshes with fewer triangles are always drawn whole (no proxy)
    int targetTriangles = 50000;  // triangles the proxy aims at; it is shaded with the full mesh's normals,
                                  // so it looks smooth even where its triangles are large
    // Largest simplification error allowed, relative to the mesh's extent (1%: about four pixels on a mesh
    // that fills an 800-pixel-high view); the simplifier stops there even above targetTriangles.
    float maxRelativeError = 0.01f;
    // From this size on, meshopt_simplifySloppy (about 0.1 s for 2M triangles) instead of meshopt_simplify
    // (edge collapse: about 1 s per million triangles, better shape).
    int sloppyFromTriangles = 1000000;
};

// The proxy's triangles, #P x 3 indices into `positions` (#V x 3), with P <= #F; empty when the mesh has
// fewer than options.minTriangles triangles or the simplifier cannot remove at least a quarter of them (the
// full mesh is then cheap enough, or the proxy would not be). triangles #F x 3, indices in [0, #V).
// Positions are converted to float relative to their bounding box's centre (any scale, any place).
Triangles buildMeshProxy(const Positions& positions, const Triangles& triangles, const MeshProxyOptions& options = {});

}  // namespace sculpt::render
