// OFF (Geomview's Object File Format, as CGAL, libigl, Geomview and MeshLab write it), read and written here.
// Not through CGAL's OFF scanner (CGAL::IO::read_OFF, libcgal-dev 5.5), which was tried first: it casts the
// file's numbers to unsigned types unchecked (a face index of -1 or a colour of 300 is undefined behaviour, and
// in practice invents a value), keeps no alpha, and does not say where it stopped. OFF is a few lines of
// grammar; this reader follows CGAL's reading of it (one vertex or face a line), but tells a colour's scale by
// how it is written, where CGAL's scanner reads "1.0 0 0" (red) as 1/255.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

// Reads an OFF file's bytes into out as faces without triangles (the caller triangulates and checks it, as for
// the other formats). Headers: OFF, COFF (vertex colours), NOFF (vertex normals), CNOFF, 4OFF (homogeneous),
// STOFF (texture coordinates), the counts on the header's line or the next; comments ('#' to the end of a
// line) and blank lines anywhere. One vertex a line: x y z [w] [nx ny nz] [r g b [a]] [s t]; one face a line:
// n i_1 ... i_n [colour]. Vertices kept in file order, in double precision exactly as written; polygons of any
// size kept as polygons; vertex colours RGB or RGBA (written as integers, as MeshLab and CGAL write them:
// 0-255; with a decimal point or an exponent: 0-1); normals and texture coordinates per vertex. Not kept, each named in notes: face colours,
// faces of fewer than 3 vertices, lines after the last face the header declares.
// Fails with "name: line L: what is wrong" (out untouched): a header that is not OFF, binary OFF, counts the
// file cannot hold, a vertex or face line with a number that does not parse or is out of range (an index
// beyond the vertices, a colour outside its scale), or too few or many numbers; a file that ends early.
Status readOffDocument(const std::string& bytes, const std::string& name, ObjMesh& out, std::vector<std::string>& notes);

// The mesh as ASCII OFF: "OFF", or "COFF" when colours has rows (#V x 4, RGBA in [0, 1]: written as integers
// 0-255 when every one is an 8-bit value, as CGAL and MeshLab read them, else as 0-1 numbers with a point), "NOFF"/"CNOFF" when normals has rows (#V x 3). Positions
// (deformed, #V x 3) as the shortest text that reads back to the same double; faces as their polygons.
std::string writeOff(const ObjMesh& mesh, const Positions& deformed, const VertexColors& colours, const VertexNormals& normals);

}  // namespace sculpt::io
