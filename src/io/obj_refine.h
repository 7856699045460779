// An OBJ mesh carried over to the mesh the engine refined (core/deform/refinement.h): the same polygons where
// nothing was split, the refined triangles where something was, and texture coordinates interpolated at
// every split.
#pragma once

#include <string>
#include <vector>

#include "core/deform/refinement.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

// `refined` = `mesh` with `splits` applied (core::applyEdgeSplits on mesh.triangles, the triangles the engine
// was given; core::Session::refinement().appliedSplits). Faces none of whose triangles was halved keep their polygon; each
// other face is written as the triangles it is made of now, in its place (same group and material), with the
// orientation of the original. Every new corner's texture coordinate is the midpoint of the texture
// coordinates the split edge's ends had *in that face* (a new `vt` per distinct pair, so a split along a seam
// gets one on each side; a corner without one stays without). New vertices get the midpoint of their edge in
// mesh.positions (the caller writes deformed positions anyway). The result has no source text: saving it
// writes every line from the arrays, with normals recomputed (one per vertex). Fails, refined untouched, on
// an invalid mesh or splits that do not fit its triangles.
Status refineObjMesh(const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits, ObjMesh& refined);

// saveObj of refineObjMesh(mesh, splits) with deformedPositions (#V + #splits rows); with no splits exactly
// saveObj(path, mesh, deformedPositions), which keeps the source text.
Status saveRefinedObj(const std::string& path, const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits,
                      const Positions& deformedPositions);

}  // namespace sculpt::io
