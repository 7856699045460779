// Welding coincident vertices: a file that stores every triangle's corners apart (a triangle soup: STL always,
// some PLY and OBJ exporters) loads as disconnected triangles, drawn faceted, each a part of its own. Welding
// makes the corners at exactly the same position one vertex (-0 and 0 are one position), so the surface is one
// connected mesh with smooth normals. STL files are always welded on load (mesh_file.h); for the other formats it
// is the window's File > Open option and the headless --weld flag.
#pragma once

#include "io/obj_mesh.h"

namespace sculpt::io {

struct WeldReport {
    int verticesBefore = 0, verticesAfter = 0;
    int trianglesCollapsed = 0;  // triangles with two corners welded into one (kept: counted apart at load)
};

// Makes the vertices of `mesh` at identical positions one, numbered in the order of their first use in the
// file (the first of each group keeps its place, the welded ones go: a save writes the vertices in that order).
// Faces, corners and triangles are renumbered; a vertex's colour and (per-vertex formats) texture coordinate are
// the first one's; the file's vertex normals are dropped (recomputed from the welded surface). The loaded text of
// an OBJ no longer matches, so a save writes the mesh afresh. Never fails; a mesh without coincident vertices is
// left exactly as it was.
WeldReport weldCoincidentVertices(ObjMesh& mesh);

// What weldCoincidentVertices would do to a mesh with these positions (#V x 3), leaving them as they are
// (trianglesCollapsed is not counted: 0).
WeldReport countCoincidentVertices(const Positions& positions);

}  // namespace sculpt::io
