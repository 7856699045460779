// The glTF writer (writeGltf, through tinygltf) and the primitives it splits a mesh into (primitiveGroups).
#include "io/mesh_file_internal.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

namespace sculpt::io::detail {

// The vertices of each group when no vertex is shared between groups and each group's vertices are consecutive,
// else one list of all (glTF primitives).
std::vector<std::vector<int>> primitiveGroups(const ObjMesh& mesh) {
    std::vector<int> groupOf(static_cast<size_t>(mesh.positions.rows()), -1);
    bool shared = false;
    for (int f = 0; f < mesh.faceCount() && !shared; ++f)
        for (int c = mesh.faceStart[f]; c < mesh.faceStart[f + 1]; ++c) {
            int& g = groupOf[static_cast<size_t>(mesh.cornerVertex[c])];
            if (g >= 0 && g != mesh.faceGroup[f]) shared = true;
            g = mesh.faceGroup[f];
        }
    // A vertex no face uses belongs to no group: one primitive then, which keeps it (and the vertex order).
    shared = shared || std::find(groupOf.begin(), groupOf.end(), -1) != groupOf.end();
    std::vector<std::vector<int>> groups(shared ? 1 : mesh.groupNames.size());
    for (int v = 0; v < mesh.positions.rows(); ++v)
        groups[shared || groupOf[static_cast<size_t>(v)] < 0 ? 0 : static_cast<size_t>(groupOf[static_cast<size_t>(v)])].push_back(v);
    groups.erase(std::remove_if(groups.begin(), groups.end(), [](const std::vector<int>& g) { return g.empty(); }), groups.end());
    // Primitives one after another must give the vertices in their order: each group a run of consecutive
    // vertices. Otherwise one primitive keeps the order (the groups are then not written, like PLY's).
    std::sort(groups.begin(), groups.end(), [](const std::vector<int>& a, const std::vector<int>& b) { return a[0] < b[0]; });
    int next = 0;
    for (const std::vector<int>& g : groups)
        for (int v : g)
            if (v != next++) {
                std::vector<int> all(static_cast<size_t>(mesh.positions.rows()));
                for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
                return {all};
            }
    return groups;
}

// glTF is written with tinygltf (Debian's libtinygltf), not assimp: assimp's glTF writer always merges vertices
// that are identical in every attribute (its JoinIdenticalVertices step cannot be turned off), which changes the
// vertex count and order. One mesh with one triangle primitive per group (primitiveGroups), each placed by its
// own node; POSITION (with its bounds, as the format requires), NORMAL, COLOR_0 (float RGBA), TEXCOORD_0 (v
// flipped: glTF's runs down the image, OBJ's and PLY's up), uint32 indices. A .gltf holds its buffer as a
// base64 data URI, so a save is one file, written atomically.
std::string writeGltf(const ObjMesh& mesh, const Positions& deformed, const MeshEncoding& encoding,
                      const SaveAttributes& attributes) {
    const Texcoords& texcoords = attributes.texcoords;
    const bool writeTexcoords = attributes.writeTexcoords;
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "DMFFD Sculpt";
    model.buffers.emplace_back();
    std::vector<unsigned char>& data = model.buffers[0].data;
    // Appends count elements of `components` floats or uint32 each, as a buffer view and an accessor.
    const auto addAccessor = [&](const std::vector<float>* floats, const std::vector<uint32_t>* indices, int components,
                                 int type, int target) {
        const size_t offset = data.size();
        const size_t bytes = floats ? floats->size() * 4 : indices->size() * 4;
        data.resize(offset + bytes);
        if (bytes > 0) std::memcpy(data.data() + offset, floats ? static_cast<const void*>(floats->data()) : indices->data(), bytes);
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = offset;
        view.byteLength = bytes;
        view.target = target;
        model.bufferViews.push_back(view);
        tinygltf::Accessor accessor;
        accessor.bufferView = static_cast<int>(model.bufferViews.size()) - 1;
        accessor.componentType = floats ? TINYGLTF_COMPONENT_TYPE_FLOAT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        accessor.count = (floats ? floats->size() : indices->size()) / static_cast<size_t>(components);
        accessor.type = type;
        model.accessors.push_back(accessor);
        return static_cast<int>(model.accessors.size()) - 1;
    };
    const VertexNormals normals = saveNormals(mesh, deformed);
    const bool colours = attributes.colours.rows() > 0;
    const std::vector<std::vector<int>>& groups = attributes.primitives;
    std::vector<int> local(static_cast<size_t>(mesh.positions.rows()), -1);
    tinygltf::Scene scene;
    for (const std::vector<int>& vertices : groups) {
        for (size_t i = 0; i < vertices.size(); ++i) local[static_cast<size_t>(vertices[i])] = static_cast<int>(i);
        std::vector<float> position, normal, colour, uv;
        std::vector<double> low(3, std::numeric_limits<double>::infinity()), high(3, -std::numeric_limits<double>::infinity());
        for (int v : vertices) {
            for (int k = 0; k < 3; ++k) {
                const float x = static_cast<float>(deformed(v, k));
                position.push_back(x);
                low[static_cast<size_t>(k)] = std::min(low[static_cast<size_t>(k)], static_cast<double>(x));
                high[static_cast<size_t>(k)] = std::max(high[static_cast<size_t>(k)], static_cast<double>(x));
                normal.push_back(normals(v, k));
            }
            for (int k = 0; k < 4 && colours; ++k) colour.push_back(attributes.colours(v, k));
            if (writeTexcoords) {
                uv.push_back(static_cast<float>(texcoords(v, 0)));
                uv.push_back(static_cast<float>(1.0 - texcoords(v, 1)));
            }
        }
        std::vector<uint32_t> indices;
        int group = 0;
        for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
            if (local[static_cast<size_t>(mesh.triangles(t, 0))] < 0) continue;  // another primitive's triangle
            if (indices.empty()) group = mesh.faceGroup[static_cast<size_t>(mesh.triangleFace[static_cast<size_t>(t)])];
            for (int k = 0; k < 3; ++k) indices.push_back(static_cast<uint32_t>(local[static_cast<size_t>(mesh.triangles(t, k))]));
        }
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.attributes["POSITION"] = addAccessor(&position, nullptr, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        model.accessors.back().minValues = low;
        model.accessors.back().maxValues = high;
        primitive.attributes["NORMAL"] = addAccessor(&normal, nullptr, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (colours) primitive.attributes["COLOR_0"] = addAccessor(&colour, nullptr, 4, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (writeTexcoords)
            primitive.attributes["TEXCOORD_0"] = addAccessor(&uv, nullptr, 2, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.indices = addAccessor(nullptr, &indices, 1, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        tinygltf::Mesh gltfMesh;
        gltfMesh.name = groups.size() > 1 ? mesh.groupNames[static_cast<size_t>(group)] : std::string("mesh");
        gltfMesh.primitives.push_back(primitive);
        model.meshes.push_back(gltfMesh);
        tinygltf::Node node;
        node.mesh = static_cast<int>(model.meshes.size()) - 1;
        node.name = gltfMesh.name;
        model.nodes.push_back(node);
        scene.nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
        for (int v : vertices) local[static_cast<size_t>(v)] = -1;
    }
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    writer.WriteGltfSceneToStream(&model, out, !encoding.binary, encoding.binary);
    return out.str();
}

}  // namespace sculpt::io::detail
