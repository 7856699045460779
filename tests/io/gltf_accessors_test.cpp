// glTF accessors as the specification defines them (glTF 2.0, section 3.6 "Binary data storage"): sparse
// substitutions on interleaved and tight buffer views, absent views (zeros), normalized integer colours, byte
// strides with padding, every index type, strips and fans. The files are written here byte by byte and the
// expected values computed here from what was written (an independent reading), never by the loader; each file
// is read as a .glb and as a .gltf with its buffer in a file beside it. Then files that break a bound are
// refused, each with a message naming the file and what is wrong, and the output left untouched.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "io_test_support.h"
#include "io/mesh_file.h"

namespace sculpt::io {

namespace {

using test::TempFolder;

// A glTF document under construction: a binary buffer, its views and accessors as JSON text.
struct Document {
    std::vector<unsigned char> bin;
    std::vector<std::string> views, accessors;
    std::string attributes;  // "\"POSITION\": 0, ..."
    std::string indices;     // ", \"indices\": N" or ""
    int mode = 4;

    void align4() {
        while (bin.size() % 4 != 0) bin.push_back(0);
    }
    // A view over [offset, offset + length) of the buffer; stride 0: none written.
    int view(size_t offset, size_t length, size_t stride) {
        std::string v = "{\"buffer\": 0, \"byteOffset\": " + std::to_string(offset) + ", \"byteLength\": " + std::to_string(length);
        if (stride > 0) v += ", \"byteStride\": " + std::to_string(stride);
        views.push_back(v + "}");
        return static_cast<int>(views.size()) - 1;
    }
    int accessor(const std::string& json) {
        accessors.push_back(json);
        return static_cast<int>(accessors.size()) - 1;
    }
    std::string json() const {
        std::string j = "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}],"
                        " \"meshes\": [{\"name\": \"part\", \"primitives\": [{\"attributes\": {" +
                        attributes + "}" + indices + ", \"mode\": " + std::to_string(mode) + "}]}], \"bufferViews\": [";
        for (size_t i = 0; i < views.size(); ++i) j += (i ? ", " : "") + views[i];
        j += "], \"accessors\": [";
        for (size_t i = 0; i < accessors.size(); ++i) j += (i ? ", " : "") + accessors[i];
        return j + "], \"buffers\": [{\"byteLength\": " + std::to_string(bin.size()) + "BUFFER_URI}]}";
    }
};

template <typename T>
void put(std::vector<unsigned char>& bin, size_t at, T value) {
    if (bin.size() < at + sizeof value) bin.resize(at + sizeof value, 0);
    std::memcpy(bin.data() + at, &value, sizeof value);
}

void put32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

// The GLB container (section 4.4): header, JSON chunk padded with spaces, BIN chunk padded with zeros.
std::string glb(const Document& d) {
    std::string json = d.json();
    json.replace(json.find("BUFFER_URI"), 10, "");
    while (json.size() % 4 != 0) json += ' ';
    std::string bin(d.bin.begin(), d.bin.end());
    while (bin.size() % 4 != 0) bin += '\0';
    std::string out = "glTF";
    put32(out, 2);
    put32(out, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    put32(out, static_cast<uint32_t>(json.size()));
    put32(out, 0x4E4F534Au);
    out += json;
    put32(out, static_cast<uint32_t>(bin.size()));
    put32(out, 0x004E4942u);
    return out + bin;
}

void writeFile(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

// What the test expects the loader to return, computed as the file was written.
struct Expected {
    std::vector<std::array<float, 3>> positions, normals;
    std::vector<std::array<double, 4>> colours;
    std::vector<std::array<int, 3>> triangles;
};

// One random valid document of n vertices and what it holds.
void randomDocument(std::mt19937& rng, int n, Document& d, Expected& e) {
    std::uniform_real_distribution<float> coordinate(-10.0f, 10.0f);
    std::uniform_int_distribution<int> coin(0, 1);
    e.positions.resize(static_cast<size_t>(n));
    e.normals.resize(static_cast<size_t>(n));
    for (int v = 0; v < n; ++v)
        for (int k = 0; k < 3; ++k) {
            e.positions[static_cast<size_t>(v)][static_cast<size_t>(k)] = coordinate(rng);
            e.normals[static_cast<size_t>(v)][static_cast<size_t>(k)] = coordinate(rng) / 10.0f;
        }
    // POSITION and NORMAL interleaved (stride 24, or with padding) or each in its own tight view.
    const bool interleaved = coin(rng) == 1;
    const bool positionView = coin(rng) == 1 || interleaved;  // false: no view, zeros under the sparse values
    int positionAccessor = 0, normalAccessor = 0;
    if (interleaved) {
        const size_t stride = 24 + 4 * static_cast<size_t>(std::uniform_int_distribution<int>(0, 2)(rng));
        const size_t start = d.bin.size();
        for (int v = 0; v < n; ++v)
            for (int k = 0; k < 3; ++k) {
                put(d.bin, start + static_cast<size_t>(v) * stride + 4 * static_cast<size_t>(k), e.positions[static_cast<size_t>(v)][static_cast<size_t>(k)]);
                put(d.bin, start + static_cast<size_t>(v) * stride + 12 + 4 * static_cast<size_t>(k), e.normals[static_cast<size_t>(v)][static_cast<size_t>(k)]);
            }
        d.bin.resize(start + static_cast<size_t>(n) * stride);
        const int view = d.view(start, static_cast<size_t>(n) * stride, stride);
        positionAccessor = d.accessor("{\"bufferView\": " + std::to_string(view) + ", \"componentType\": 5126, \"count\": " +
                                      std::to_string(n) + ", \"type\": \"VEC3\"SPARSE}");
        normalAccessor = d.accessor("{\"bufferView\": " + std::to_string(view) + ", \"byteOffset\": 12, \"componentType\": 5126, \"count\": " +
                                    std::to_string(n) + ", \"type\": \"VEC3\"}");
    } else {
        std::string positionJson = "{\"componentType\": 5126, \"count\": " + std::to_string(n) + ", \"type\": \"VEC3\"SPARSE}";
        if (positionView) {
            const size_t start = d.bin.size();
            for (int v = 0; v < n; ++v)
                for (int k = 0; k < 3; ++k) put(d.bin, d.bin.size(), e.positions[static_cast<size_t>(v)][static_cast<size_t>(k)]);
            positionJson.insert(1, "\"bufferView\": " + std::to_string(d.view(start, d.bin.size() - start, 0)) + ", ");
        } else {
            for (auto& p : e.positions) p = {0.0f, 0.0f, 0.0f};
        }
        positionAccessor = d.accessor(positionJson);
        const size_t start = d.bin.size();
        for (int v = 0; v < n; ++v)
            for (int k = 0; k < 3; ++k) put(d.bin, d.bin.size(), e.normals[static_cast<size_t>(v)][static_cast<size_t>(k)]);
        normalAccessor = d.accessor("{\"bufferView\": " + std::to_string(d.view(start, d.bin.size() - start, 0)) +
                                    ", \"componentType\": 5126, \"count\": " + std::to_string(n) + ", \"type\": \"VEC3\"}");
    }
    // The sparse substitution of POSITION: k distinct increasing indices, each replaced by a new value. Without
    // a view every vertex must be given, or the mesh would collapse to the origin.
    std::vector<int> all(static_cast<size_t>(n));
    for (int v = 0; v < n; ++v) all[static_cast<size_t>(v)] = v;
    std::shuffle(all.begin(), all.end(), rng);
    const int k = positionView ? std::uniform_int_distribution<int>(1, n)(rng) : n;
    std::vector<int> replaced(all.begin(), all.begin() + k);
    std::sort(replaced.begin(), replaced.end());
    const int indexType = n <= 255 && coin(rng) ? 5121 : coin(rng) ? 5123 : 5125;
    const size_t indexBytes = indexType == 5121 ? 1 : indexType == 5123 ? 2 : 4;
    d.align4();
    const size_t indexStart = d.bin.size();
    for (int r : replaced) {
        if (indexBytes == 1) put(d.bin, d.bin.size(), static_cast<uint8_t>(r));
        if (indexBytes == 2) put(d.bin, d.bin.size(), static_cast<uint16_t>(r));
        if (indexBytes == 4) put(d.bin, d.bin.size(), static_cast<uint32_t>(r));
    }
    const int indexView = d.view(indexStart, d.bin.size() - indexStart, 0);
    d.align4();
    const size_t valueStart = d.bin.size();
    for (int r : replaced)
        for (int c = 0; c < 3; ++c) {
            const float x = coordinate(rng);
            e.positions[static_cast<size_t>(r)][static_cast<size_t>(c)] = x;
            put(d.bin, d.bin.size(), x);
        }
    const int valueView = d.view(valueStart, d.bin.size() - valueStart, 0);
    std::string& position = d.accessors[static_cast<size_t>(positionAccessor)];
    position.replace(position.find("SPARSE"), 6,
                     ", \"sparse\": {\"count\": " + std::to_string(k) + ", \"indices\": {\"bufferView\": " + std::to_string(indexView) +
                         ", \"componentType\": " + std::to_string(indexType) + "}, \"values\": {\"bufferView\": " +
                         std::to_string(valueView) + "}}");
    // COLOR_0: normalized unsigned bytes (RGBA) or shorts (RGB), or floats.
    const int colourKind = std::uniform_int_distribution<int>(0, 2)(rng);
    d.align4();
    const size_t colourStart = d.bin.size();
    e.colours.resize(static_cast<size_t>(n));
    for (int v = 0; v < n; ++v) {
        auto& c = e.colours[static_cast<size_t>(v)];
        c = {1.0, 1.0, 1.0, 1.0};
        if (colourKind == 0) {
            // Each element padded to 4 bytes, as the specification asks of vertex attributes.
            for (int j = 0; j < 4; ++j) {
                const auto byte = static_cast<uint8_t>(std::uniform_int_distribution<int>(0, 255)(rng));
                put(d.bin, d.bin.size(), byte);
                c[static_cast<size_t>(j)] = byte / 255.0;
            }
        } else if (colourKind == 1) {
            for (int j = 0; j < 3; ++j) {
                const auto s = static_cast<uint16_t>(std::uniform_int_distribution<int>(0, 65535)(rng));
                put(d.bin, d.bin.size(), s);
                c[static_cast<size_t>(j)] = s / 65535.0;
            }
            put(d.bin, d.bin.size(), static_cast<uint16_t>(0));  // padding: stride 8
        } else {
            for (int j = 0; j < 4; ++j) {
                const float f = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
                put(d.bin, d.bin.size(), f);
                c[static_cast<size_t>(j)] = f;
            }
        }
    }
    const size_t colourStride = colourKind == 0 ? 4 : colourKind == 1 ? 8 : 16;
    const int colourView = d.view(colourStart, d.bin.size() - colourStart, colourKind == 1 ? colourStride : 0);
    const int colourAccessor =
        d.accessor("{\"bufferView\": " + std::to_string(colourView) + ", \"componentType\": " +
                   std::string(colourKind == 0 ? "5121" : colourKind == 1 ? "5123" : "5126") + ", \"count\": " + std::to_string(n) +
                   (colourKind == 2 ? "" : ", \"normalized\": true") + ", \"type\": \"" + (colourKind == 1 ? "VEC3" : "VEC4") + "\"}");
    d.attributes = "\"POSITION\": " + std::to_string(positionAccessor) + ", \"NORMAL\": " + std::to_string(normalAccessor) +
                   ", \"COLOR_0\": " + std::to_string(colourAccessor);
    // Topology: a list of random triangles, or a strip or a fan over a random vertex sequence (section 3.7.2.1).
    d.mode = 4 + std::uniform_int_distribution<int>(0, 2)(rng);
    std::vector<uint32_t> sequence;
    std::uniform_int_distribution<int> vertex(0, n - 1);
    if (d.mode == 4) {
        const int triangles = std::uniform_int_distribution<int>(1, 2 * n)(rng);
        for (int t = 0; t < triangles; ++t) {
            std::array<int, 3> c{};
            do {
                c = {vertex(rng), vertex(rng), vertex(rng)};
            } while (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]);
            for (int j : c) sequence.push_back(static_cast<uint32_t>(j));
            e.triangles.push_back(c);
        }
    } else {
        // Distinct vertices in random order, so no triangle repeats a corner.
        std::shuffle(all.begin(), all.end(), rng);
        for (int v : all) sequence.push_back(static_cast<uint32_t>(v));
        for (size_t t = 0; t + 2 < sequence.size(); ++t) {
            const auto at = [&](size_t i) { return static_cast<int>(sequence[i]); };
            if (d.mode == 5) e.triangles.push_back({at(t), at(t + 1 + t % 2), at(t + 2 - t % 2)});
            else e.triangles.push_back({at(t + 1), at(t + 2), at(0)});
        }
    }
    const int triangleIndexType = n <= 255 && coin(rng) ? 5121 : coin(rng) ? 5123 : 5125;
    d.align4();
    const size_t triangleStart = d.bin.size();
    for (uint32_t i : sequence) {
        if (triangleIndexType == 5121) put(d.bin, d.bin.size(), static_cast<uint8_t>(i));
        if (triangleIndexType == 5123) put(d.bin, d.bin.size(), static_cast<uint16_t>(i));
        if (triangleIndexType == 5125) put(d.bin, d.bin.size(), i);
    }
    const int triangleView = d.view(triangleStart, d.bin.size() - triangleStart, 0);
    d.indices = ", \"indices\": " + std::to_string(d.accessor("{\"bufferView\": " + std::to_string(triangleView) + ", \"componentType\": " +
                                                              std::to_string(triangleIndexType) + ", \"count\": " +
                                                              std::to_string(sequence.size()) + ", \"type\": \"SCALAR\"}"));
    d.align4();
}

// The document as a .glb and as a .gltf with its buffer in data.bin beside it; returns the two paths.
std::vector<std::string> writeBoth(const TempFolder& folder, const Document& d, const std::string& stem) {
    const std::string glbPath = folder.file(stem + ".glb");
    writeFile(glbPath, glb(d));
    const std::string gltfPath = folder.file(stem + ".gltf");
    std::string json = d.json();
    json.replace(json.find("BUFFER_URI"), 10, ", \"uri\": \"" + stem + ".bin\"");
    writeFile(gltfPath, json);
    writeFile(folder.file(stem + ".bin"), std::string(d.bin.begin(), d.bin.end()));
    return {glbPath, gltfPath};
}

}  // namespace

TEST_CASE("glTF: sparse accessors on interleaved and tight views, normalized colours, strips and fans load exactly",
          "[io][formats][gltf]") {
    TempFolder folder("gltf_accessors");
    std::mt19937 rng(2026);
    int files = 0, interleavedSparse = 0;
    for (int n : {3, 4, 7, 17, 64, 255, 256, 300, 1000}) {
        for (int trial = 0; trial < 4; ++trial) {
            Document d;
            Expected e;
            randomDocument(rng, n, d, e);
            interleavedSparse += d.views[0].find("byteStride") != std::string::npos;
            for (const std::string& path : writeBoth(folder, d, "m")) {
                INFO(path << " n " << n << " trial " << trial << "\n" << d.json());
                ObjMesh mesh;
                std::vector<std::string> warnings;
                const Status s = loadMesh(path, mesh, &warnings);
                INFO(s.message);
                REQUIRE(s.ok);
                ++files;
                REQUIRE(mesh.positions.rows() == n);
                for (int v = 0; v < n; ++v)
                    for (int k = 0; k < 3; ++k) {
                        CHECK(mesh.positions(v, k) == static_cast<double>(e.positions[static_cast<size_t>(v)][static_cast<size_t>(k)]));
                        CHECK(mesh.vertexNormals(v, k) == static_cast<double>(e.normals[static_cast<size_t>(v)][static_cast<size_t>(k)]));
                    }
                REQUIRE(mesh.vertexColors.rows() == n);
                for (int v = 0; v < n; ++v)
                    for (int k = 0; k < 4; ++k)
                        CHECK(std::abs(mesh.vertexColors(v, k) - e.colours[static_cast<size_t>(v)][static_cast<size_t>(k)]) <= 1e-7);
                REQUIRE(mesh.faceCount() == static_cast<int>(e.triangles.size()));
                for (int f = 0; f < mesh.faceCount(); ++f) {
                    REQUIRE(mesh.faceStart[static_cast<size_t>(f) + 1] - mesh.faceStart[static_cast<size_t>(f)] == 3);
                    for (int k = 0; k < 3; ++k)
                        CHECK(mesh.cornerVertex[static_cast<size_t>(mesh.faceStart[static_cast<size_t>(f)] + k)] ==
                              e.triangles[static_cast<size_t>(f)][static_cast<size_t>(k)]);
                }
                for (const std::string& w : warnings) CHECK(w.find("tinygltf") == std::string::npos);
            }
        }
    }
    CHECK(files == 9 * 4 * 2);
    CHECK(interleavedSparse > 3);
}

TEST_CASE("glTF: a file that breaks an accessor's, view's or sparse part's bounds is refused naming what is wrong",
          "[io][formats][gltf]") {
    TempFolder folder("gltf_bounds");
    std::mt19937 rng(7);
    // Each break: a text replaced in the document's JSON (its first occurrence after `after`), and a phrase the
    // message must hold.
    struct Break {
        std::string after, from, to, phrase;
    };
    const std::vector<Break> breaks = {
        {"\"sparse\"", "\"count\": ", "\"count\": 99999", "replaces"},                     // more than the accessor holds
        {"\"accessors\"", "\"count\": ", "\"count\": 9999", "run past the end of buffer view|elements, POSITION 9999"},  // POSITION too long
        {"\"bufferViews\"", "\"byteLength\": ", "\"byteLength\": 1", "run past the end"},      // the first view cut short
        {"\"bufferViews\"", "\"byteOffset\": 0", "\"byteOffset\": 4000000", "runs past the end of buffer"},
        {"\"indices\": {", "\"bufferView\": ", "\"bufferView\": 77", "which does not exist"},
        {"\"attributes\"", "\"POSITION\": ", "\"POSITION\": 50", "which does not exist"},
        {"\"accessors\"", "\"type\": \"VEC3\"", "\"type\": \"MAT4\"", "which this attribute cannot be"},
        {"\"meshes\"", "\"mode\": ", "\"mode\": 9", "which glTF does not define"},
    };
    int refused = 0;
    for (int trial = 0; trial < 6; ++trial) {
        Document d;
        Expected e;
        randomDocument(rng, 40 + trial * 13, d, e);
        for (const Break& b : breaks) {
            std::string json = d.json();
            const size_t anchor = json.find(b.after);
            REQUIRE(anchor != std::string::npos);
            const size_t at = json.find(b.from, anchor);
            REQUIRE(at != std::string::npos);
            // The number after `from` is replaced whole.
            size_t end = at + b.from.size();
            while (end < json.size() && (std::isdigit(static_cast<unsigned char>(json[end])) || json[end] == '-')) ++end;
            json.replace(at, end - at, b.to);
            json.replace(json.find("BUFFER_URI"), 10, ", \"uri\": \"b.bin\"");
            const std::string path = folder.file("b.gltf");
            writeFile(path, json);
            writeFile(folder.file("b.bin"), std::string(d.bin.begin(), d.bin.end()));
            ObjMesh mesh;
            const Status s = loadMesh(path, mesh);
            INFO(b.to << ": " << s.message);
            CHECK_FALSE(s.ok);
            CHECK(s.message.rfind(path + ": ", 0) == 0);
            // Alternatives split by '|': the same break meets a different check where the layout differs (an
            // accessor with no view is zeros, so its count meets the next attribute's count instead).
            bool named = false;
            for (size_t from = 0; from <= b.phrase.size();) {
                size_t bar = b.phrase.find('|', from);
                if (bar == std::string::npos) bar = b.phrase.size();
                named |= s.message.find(b.phrase.substr(from, bar - from)) != std::string::npos;
                from = bar + 1;
            }
            CHECK(named);
            CHECK(mesh.positions.rows() == 0);
            refused += !s.ok;
        }
    }
    CHECK(refused == 6 * static_cast<int>(breaks.size()));
    // Sparse indices that are not increasing, or beyond the accessor: written here as a sparse part whose index
    // view holds a bad sequence.
    for (const std::vector<uint32_t>& bad : std::vector<std::vector<uint32_t>>{{2, 1}, {0, 0}, {0, 3}}) {
        Document d;
        const float corners[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        for (float c : corners) put(d.bin, d.bin.size(), c);
        const int positions = d.view(0, 36, 0);
        for (uint32_t i : bad) put(d.bin, d.bin.size(), i);
        const int indexView = d.view(36, 8, 0);
        for (int i = 0; i < 6; ++i) put(d.bin, d.bin.size(), 5.0f);
        const int valueView = d.view(44, 24, 0);
        d.accessor("{\"bufferView\": " + std::to_string(positions) + ", \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\","
                   " \"sparse\": {\"count\": 2, \"indices\": {\"bufferView\": " + std::to_string(indexView) +
                   ", \"componentType\": 5125}, \"values\": {\"bufferView\": " + std::to_string(valueView) + "}}}");
        d.attributes = "\"POSITION\": 0";
        const std::string path = folder.file("s.glb");
        writeFile(path, glb(d));
        ObjMesh mesh;
        const Status s = loadMesh(path, mesh);
        INFO(s.message);
        CHECK_FALSE(s.ok);
        CHECK(s.message.find("the sparse part of accessor 0") != std::string::npos);
        CHECK(s.message.find(bad[1] >= 3 ? "beyond the accessor's 3 elements" : "not above the index before it") != std::string::npos);
    }
}

}  // namespace sculpt::io

namespace sculpt::io {

// The fuzz seeds (tests/fuzz/make_gltf_corpus.py) are valid files of the kinds the reader checks; they load
// with the values their generator wrote.
TEST_CASE("glTF: the fuzz seed files load with the values written", "[io][formats][gltf]") {
    const std::string dir = std::string(SCULPT_SOURCE_DIR) + "/tests/fuzz/corpus_gltf/";
    ObjMesh interleaved, zeros, fan;
    REQUIRE(loadMesh(dir + "interleaved_sparse.glb", interleaved).ok);
    REQUIRE(interleaved.positions.rows() == 6);
    Positions expected(6, 3);
    expected << 0, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 2, 1, 0, 1;  // vertices 1 and 4 from the sparse part
    CHECK(interleaved.positions == expected);
    CHECK(interleaved.faceCount() == 2);
    REQUIRE(loadMesh(dir + "zeros_sparse_strip.glb", zeros).ok);
    Positions strip(5, 3);
    strip << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0;
    CHECK(zeros.positions == strip);
    CHECK(zeros.faceCount() == 3);
    REQUIRE(zeros.vertexColors.rows() == 5);
    CHECK(std::abs(zeros.vertexColors(1, 3) - 128.0 / 255.0) < 1e-7);
    REQUIRE(loadMesh(dir + "fan_ushort_colours.glb", fan).ok);
    CHECK(fan.faceCount() == 4);
    REQUIRE(fan.vertexColors.rows() == 6);
    CHECK(std::abs(fan.vertexColors(5, 1) - 5000.0 / 65535.0) < 1e-7);
    CHECK(fan.vertexColors(5, 3) == 1.0f);
}

}  // namespace sculpt::io
