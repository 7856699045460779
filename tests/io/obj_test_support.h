// Shared by the OBJ tests: two loads of a mesh hold the same faces and attributes.
#pragma once

#include <catch2/catch.hpp>

#include "io/obj_mesh.h"

namespace sculpt::test {

// Same faces (corners, texture coordinate ids), groups and materials: what any writer keeps.
inline void requireSameFaceStructure(const io::ObjMesh& a, const io::ObjMesh& b) {
    REQUIRE(a.faceStart == b.faceStart);
    REQUIRE(a.cornerVertex == b.cornerVertex);
    REQUIRE(a.cornerTexcoord == b.cornerTexcoord);
    REQUIRE(a.faceGroup == b.faceGroup);
    REQUIRE(a.groupNames == b.groupNames);
    REQUIRE(a.faceMaterial == b.faceMaterial);
    REQUIRE(a.materialNames == b.materialNames);
}

// All of that, and the same vertex count, normals per corner, texture coordinates and material libraries:
// what a save of the loaded file's own text keeps.
inline void requireSameFaces(const io::ObjMesh& a, const io::ObjMesh& b) {
    REQUIRE(a.vertexCount() == b.vertexCount());
    requireSameFaceStructure(a, b);
    REQUIRE(a.cornerNormal == b.cornerNormal);
    REQUIRE(a.texcoords == b.texcoords);
    REQUIRE(a.materialLibraries == b.materialLibraries);
}

}  // namespace sculpt::test
