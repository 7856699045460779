// Structure-aware fuzz target for the glTF reader (io/gltf_read.h through loadMeshFromMemory). Inputs are GLB
// files; the custom mutator keeps the container whole (header, JSON chunk, BIN chunk, with their lengths) and
// mutates what is inside: a number of the JSON (counts, offsets, strides, component types, indices, modes) set
// to a boundary value, the JSON text or the binary buffer changed by libFuzzer's own byte mutations, or a
// sparse part added to an accessor. So most inputs reach the accessor checks instead of failing at the container.
// Invariants: a load either fails with a message naming the file, leaving the output untouched, or gives a
// consistent mesh every value of which is in the file: each position, normal and colour component (with no
// node transform, which would compute new values) is one the BIN chunk holds at some byte offset as a float or
// a (normalized) integer, or zero (an accessor with no view), or one (a colour's missing alpha).
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <random>
#include <string>
#include <unordered_set>
#include <vector>

#include "fuzz_checks.h"
#include "io/mesh_file.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t maxSize);

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) { sculpt::fuzz::fail("gltf_fuzz", what, detail); }

struct Glb {
    std::string json, bin;
};

uint32_t read32(const std::string& s, size_t at) {
    uint32_t v = 0;
    if (at + 4 <= s.size()) std::memcpy(&v, s.data() + at, 4);
    return v;
}

void put32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

// The JSON and BIN chunks of a GLB (false when it is not one).
bool split(const std::string& bytes, Glb& out) {
    if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0) return false;
    const uint32_t jsonLength = read32(bytes, 12);
    if (read32(bytes, 16) != 0x4E4F534Au || 20ull + jsonLength > bytes.size()) return false;
    out.json = bytes.substr(20, jsonLength);
    const size_t binAt = 20 + jsonLength;
    out.bin.clear();
    if (binAt + 8 <= bytes.size() && read32(bytes, binAt + 4) == 0x004E4942u) {
        const uint32_t binLength = read32(bytes, binAt);
        out.bin = bytes.substr(binAt + 8, std::min<size_t>(binLength, bytes.size() - binAt - 8));
    }
    return true;
}

std::string join(Glb g) {
    while (g.json.size() % 4 != 0) g.json += ' ';
    while (g.bin.size() % 4 != 0) g.bin += '\0';
    std::string out = "glTF";
    put32(out, 2);
    put32(out, static_cast<uint32_t>(12 + 8 + g.json.size() + (g.bin.empty() ? 0 : 8 + g.bin.size())));
    put32(out, static_cast<uint32_t>(g.json.size()));
    put32(out, 0x4E4F534Au);
    out += g.json;
    if (!g.bin.empty()) {
        put32(out, static_cast<uint32_t>(g.bin.size()));
        put32(out, 0x004E4942u);
        out += g.bin;
    }
    return out;
}

// Every value a component of the buffer could decode to (glTF 2.0 section 3.6.2.2 and the normalization
// formulas of section 3.11), at every byte offset.
// Each also rounded to float, as the mesh's float-valued attributes (normals, colours) hold it.
std::unordered_set<double> valuesHeld(const std::string& bin) {
    std::unordered_set<double> held{0.0, 1.0};
    const auto* p = reinterpret_cast<const unsigned char*>(bin.data());
    for (size_t at = 0; at < bin.size(); ++at) {
        const int8_t s8 = static_cast<int8_t>(p[at]);
        held.insert(p[at]);
        held.insert(p[at] / 255.0);
        held.insert(s8);
        held.insert(std::max(s8 / 127.0, -1.0));
        if (at + 2 <= bin.size()) {
            uint16_t u16;
            int16_t s16;
            std::memcpy(&u16, p + at, 2);
            std::memcpy(&s16, p + at, 2);
            held.insert(u16);
            held.insert(u16 / 65535.0);
            held.insert(s16);
            held.insert(std::max(s16 / 32767.0, -1.0));
        }
        if (at + 4 <= bin.size()) {
            float f;
            uint32_t u32;
            std::memcpy(&f, p + at, 4);
            std::memcpy(&u32, p + at, 4);
            held.insert(static_cast<double>(f));
            held.insert(static_cast<double>(u32));
        }
    }
    std::unordered_set<double> withFloats = held;
    for (double v : held) withFloats.insert(static_cast<double>(static_cast<float>(v)));
    return withFloats;
}

}  // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t maxSize, unsigned int seed) {
    Glb g;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    if (!split(bytes, g)) return LLVMFuzzerMutate(data, size, maxSize);
    std::mt19937 rng(seed);
    const int choice = std::uniform_int_distribution<int>(0, 9)(rng);
    if (choice <= 4) {
        // A number of the JSON set to a boundary value.
        std::vector<size_t> numbers;
        for (size_t i = 0; i < g.json.size(); ++i)
            if (std::isdigit(static_cast<unsigned char>(g.json[i])) && (i == 0 || !std::isalnum(static_cast<unsigned char>(g.json[i - 1])) ||
                                                                        g.json[i - 1] == '-'))
                numbers.push_back(i);
        if (!numbers.empty()) {
            const size_t at = numbers[std::uniform_int_distribution<size_t>(0, numbers.size() - 1)(rng)];
            size_t end = at;
            while (end < g.json.size() && (std::isdigit(static_cast<unsigned char>(g.json[end])) || g.json[end] == '.')) ++end;
            static const char* boundaries[] = {"0", "1", "2", "3", "4", "5", "6", "12", "24", "252", "253", "255", "256",
                                               "65535", "65536", "2147483647", "4294967295", "4294967296", "-1",
                                               "5120", "5121", "5122", "5123", "5125", "5126"};
            const std::string value = std::uniform_int_distribution<int>(0, 1)(rng)
                                          ? boundaries[std::uniform_int_distribution<size_t>(0, std::size(boundaries) - 1)(rng)]
                                          : std::to_string(std::uniform_int_distribution<int>(0, 300)(rng));
            g.json.replace(at, end - at, value);
        }
    } else if (choice <= 6) {
        // libFuzzer's mutations of the binary buffer.
        std::string bin = g.bin;
        bin.resize(std::max<size_t>(bin.size() + 64, 64));
        bin.resize(LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(bin.data()), g.bin.size(), bin.size()));
        g.bin = bin;
    } else if (choice == 7) {
        // A sparse part on an accessor: indices and values from views that exist.
        const size_t at = g.json.find("\"componentType\"");
        if (at != std::string::npos) {
            const int count = std::uniform_int_distribution<int>(1, 4)(rng);
            const int view = std::uniform_int_distribution<int>(0, 3)(rng);
            g.json.insert(at, "\"sparse\": {\"count\": " + std::to_string(count) + ", \"indices\": {\"bufferView\": " +
                                  std::to_string(view) + ", \"componentType\": 5121}, \"values\": {\"bufferView\": " +
                                  std::to_string((view + 1) % 4) + "}}, ");
        }
    } else {
        // libFuzzer's mutations of the JSON text.
        std::string json = g.json;
        json.resize(json.size() + 64);
        json.resize(LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(json.data()), g.json.size(), json.size()));
        g.json = json;
    }
    const std::string out = join(g);
    if (out.size() > maxSize) return size;
    std::memcpy(data, out.data(), out.size());
    return out.size();
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sculpt::io;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    const std::string name = "fuzz.glb";
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const sculpt::Status loaded = loadMeshFromMemory(bytes, MeshFormat::Gltf, name, mesh, &warnings);
    if (!sculpt::fuzz::checkLoad("gltf_fuzz", loaded, name, mesh, warnings)) return 0;
    bool transformed = false;
    for (const std::string& w : warnings) transformed |= w.find("node transforms are applied") != std::string::npos;
    Glb g;
    // A JSON glTF, or a GLB with buffers as data URIs, holds values outside the BIN chunk: not checked here.
    if (transformed || !split(bytes, g) || g.json.find("data:") != std::string::npos) return 0;
    const std::unordered_set<double> held = valuesHeld(g.bin);
    const auto check = [&](const auto& matrix, const char* what) {
        for (Eigen::Index r = 0; r < matrix.rows(); ++r)
            for (Eigen::Index c = 0; c < matrix.cols(); ++c)
                if (!held.count(static_cast<double>(matrix(r, c))))
                    fail("a loaded value is not in the file", std::string(what) + " " + std::to_string(r) + "," + std::to_string(c) +
                                                                   " = " + std::to_string(static_cast<double>(matrix(r, c))));
    };
    check(mesh.positions, "position");
    check(mesh.vertexNormals, "normal");
    check(mesh.vertexColors, "colour");
    if (mesh.texcoords.rows() > 0) check(mesh.texcoords.leftCols(1), "texture coordinate u");
    return 0;
}
