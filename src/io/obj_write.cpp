// OBJ writing: shortest round-trip numbers. A loaded mesh is its source text with the changed numbers
// replaced (everything else byte for byte); a mesh built in code is written from its arrays with recomputed
// normals and the polygons/groups/materials it has.
#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstring>
#include <new>
#include <string_view>

#include <Eigen/Geometry>

#include <omp.h>

#include "core/deform/vertex_normals.h"
#include "io/atomic_file.h"
#include "io/huge_pages.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

namespace {

// Text written through a cursor into a std::string whose reserved storage is made writable ahead (room()):
// a number or a character is then a store, not a call of std::string's append with its length checks, which
// was a third of save_obj_1m. The string has its used length again when the cursor goes.
class TextCursor {
public:
    explicit TextCursor(std::string& text) : text_(text), used_(text.size()) {}
    ~TextCursor() { text_.resize(used_); }
    TextCursor(const TextCursor&) = delete;
    TextCursor& operator=(const TextCursor&) = delete;
    // Makes at least n more bytes writable (storage doubled, advised for huge pages, when it runs out).
    void room(size_t n) {
        if (text_.size() - used_ >= n) return;
        if (text_.capacity() < used_ + n) reserveWithHugePages(text_, std::max(used_ + n, 2 * text_.capacity()));
        text_.resize(text_.capacity());
    }
    // The writes below need room: one character, or kNumberRoom bytes for a number.
    static constexpr size_t kNumberRoom = 32;
    void put(char c) { text_[used_++] = c; }
    // Checks its own room.
    void put(std::string_view s) {
        room(s.size());
        std::memcpy(&text_[used_], s.data(), s.size());
        used_ += s.size();
    }
    // note: std::to_chars without a precision prints the shortest text that reads back to the very same double
    // or float (Ryu; a float's own "0.08235294", not its double's 17 digits), locale-independent; "%.17g" would
    // also round-trip but is longer and obeys LC_NUMERIC (a German locale would write "0,5").
    template <typename Number>
    void number(Number value) {
        char* at = &text_[used_];
        used_ += static_cast<size_t>(std::to_chars(at, at + kNumberRoom, value).ptr - at);
    }

private:
    std::string& text_;
    size_t used_;
};

// Appends format(row, cursor) for rows 0..n-1 to out, in order. A big section is formatted in chunks on every
// thread (a 1M-vertex OBJ has 4M lines: half of save_obj_1m was formatting), then appended chunk by chunk.
// format must write only through its cursor. Throws std::bad_alloc as the serial loop would.
template <typename Format>
void appendRowsInParallel(std::string& out, Eigen::Index n, const Format& format) {
    constexpr Eigen::Index kSerialRows = 32768;
    if (n <= kSerialRows) {
        TextCursor cursor(out);
        for (Eigen::Index r = 0; r < n; ++r) format(r, cursor);
        return;
    }
    const int chunks = 4 * omp_get_max_threads();
    std::vector<std::string> parts(static_cast<size_t>(chunks));
    std::atomic<bool> outOfMemory{false};
#pragma omp parallel for schedule(dynamic, 1)
    for (int c = 0; c < chunks; ++c) {
        try {
            std::string& part = parts[static_cast<size_t>(c)];
            const Eigen::Index first = n * c / chunks, last = n * (c + 1) / chunks;
            reserveWithHugePages(part, static_cast<size_t>(last - first) * 96);  // a `v` or `vn` line is 50-70 bytes, an `f` line 30-45
            TextCursor cursor(part);
            for (Eigen::Index r = first; r < last; ++r) format(r, cursor);
        } catch (const std::bad_alloc&) {
            outOfMemory = true;  // no exception may leave an OpenMP region
        }
    }
    if (outOfMemory) throw std::bad_alloc();
    for (std::string& part : parts) {
        out += part;
        std::string().swap(part);  // freed as it goes: peak memory stays near one copy
    }
}

bool hasLineBreak(const std::string& s) {
    for (char c : s)
        if (c == '\n' || c == '\r' || c == '\0') return true;
    return false;
}

bool sameBits(const Positions& a, const Positions& b, Eigen::Index row) {
    return std::memcmp(a.row(row).data(), b.row(row).data(), 3 * sizeof(double)) == 0;
}

bool spansAreOrdered(const std::vector<size_t>& spans, size_t textSize) {
    size_t previousEnd = 0;
    for (size_t i = 0; i + 1 < spans.size(); i += 2) {
        if (spans[i] < previousEnd || spans[i + 1] <= spans[i] || spans[i + 1] > textSize) return false;
        previousEnd = spans[i + 1];
    }
    return spans.size() % 2 == 0;
}

// Two ordered span lists (spansAreOrdered) share no byte.
bool spansAreDisjoint(const std::vector<size_t>& a, const std::vector<size_t>& b) {
    size_t i = 0, j = 0;
    while (i + 1 < a.size() && j + 1 < b.size()) {
        if (a[i + 1] <= b[j]) {
            i += 2;
        } else if (b[j + 1] <= a[i]) {
            j += 2;
        } else {
            return false;
        }
    }
    return true;
}

// The source text with the x y z of moved vertices and the normals of changed faces replaced (see serializeObj).
void writeFromSource(const ObjMesh& mesh, const Positions& deformed, std::string& out) {
    const ObjSource& source = *mesh.source;
    const Eigen::Index vertexCount = deformed.rows();
    std::vector<char> moved(static_cast<size_t>(vertexCount), 0);
    for (Eigen::Index v = 0; v < vertexCount; ++v) moved[static_cast<size_t>(v)] = !sameBits(deformed, mesh.positions, v);

    // A `vn` used by a corner of a face that changed shape (a vertex of it moved) gets the normalised sum of
    // the Newell normals (twice the area times the unit normal) of the deformed faces of all its corners: the
    // area-weighted vertex normal where the file has one normal per vertex, and hard edges stay hard where it
    // shares one per smooth patch. The others are the file's own, still right for faces that did not change.
    const size_t normalCount = source.normalSpans.size() / 2;
    std::vector<char> stale(normalCount, 0);
    for (int f = 0; f < mesh.faceCount(); ++f) {
        const int first = mesh.faceStart[f], end = mesh.faceStart[f + 1];
        bool changed = false;
        for (int c = first; c < end && !changed; ++c) changed = moved[static_cast<size_t>(mesh.cornerVertex[c])];
        if (!changed) continue;
        for (int c = first; c < end; ++c)
            if (mesh.cornerNormal[c] >= 0) stale[static_cast<size_t>(mesh.cornerNormal[c])] = 1;
    }
    std::vector<Eigen::Vector3d> normalSum;
    if (std::find(stale.begin(), stale.end(), 1) != stale.end()) {
        normalSum.assign(normalCount, Eigen::Vector3d::Zero());
        for (int f = 0; f < mesh.faceCount(); ++f) {
            const int first = mesh.faceStart[f], end = mesh.faceStart[f + 1];
            bool needed = false;
            for (int c = first; c < end && !needed; ++c)
                needed = mesh.cornerNormal[c] >= 0 && stale[static_cast<size_t>(mesh.cornerNormal[c])];
            if (!needed) continue;
            const Eigen::Vector3d origin = deformed.row(mesh.cornerVertex[first]).transpose();
            Eigen::Vector3d faceNormal = Eigen::Vector3d::Zero();
            for (int c = first + 1; c + 1 < end; ++c)
                faceNormal += (deformed.row(mesh.cornerVertex[c]).transpose() - origin)
                                  .cross(deformed.row(mesh.cornerVertex[c + 1]).transpose() - origin);
            for (int c = first; c < end; ++c)
                if (mesh.cornerNormal[c] >= 0) normalSum[static_cast<size_t>(mesh.cornerNormal[c])] += faceNormal;
        }
    }

    // The replacements in text order (v and vn lines interleave in the file: both span lists walked by offset),
    // then formatted in parallel (appendRowsInParallel), each with the source text before it.
    struct Replacement {
        size_t begin, end;
        Eigen::Vector3d xyz;
    };
    std::vector<Replacement> replacements;
    size_t v = 0, n = 0;
    for (;;) {
        while (v < static_cast<size_t>(vertexCount) && !moved[v]) ++v;
        while (n < normalCount) {
            if (stale[n]) {
                const double length = normalSum[n].norm();
                if (length > 0.0 && std::isfinite(length)) break;
            }
            ++n;
        }
        const bool haveVertex = v < static_cast<size_t>(vertexCount), haveNormal = n < normalCount;
        if (!haveVertex && !haveNormal) break;
        if (haveVertex && (!haveNormal || source.positionSpans[2 * v] < source.normalSpans[2 * n])) {
            replacements.push_back({source.positionSpans[2 * v], source.positionSpans[2 * v + 1],
                                    deformed.row(static_cast<Eigen::Index>(v)).transpose()});
            ++v;
        } else {
            replacements.push_back({source.normalSpans[2 * n], source.normalSpans[2 * n + 1], normalSum[n].normalized()});
            ++n;
        }
    }
    // Overlapping spans: checkObjMesh refuses them, never expected here; such a replacement is left out.
    size_t kept = 0, lastEnd = 0;
    for (const Replacement& r : replacements)
        if (r.begin >= lastEnd) {
            replacements[kept++] = r;
            lastEnd = r.end;
        }
    replacements.resize(kept);

    reserveWithHugePages(out, source.text.size() + source.text.size() / 8 + 64);
    // Row i of the output: the source text from the replacement before it up to it, then its numbers.
    const std::string_view text(source.text);
    appendRowsInParallel(out, static_cast<Eigen::Index>(replacements.size()), [&](Eigen::Index i, TextCursor& cursor) {
        const Replacement& r = replacements[static_cast<size_t>(i)];
        const size_t copied = i == 0 ? 0 : replacements[static_cast<size_t>(i) - 1].end;  // written up to here
        cursor.put(text.substr(copied, r.begin - copied));
        cursor.room(3 * TextCursor::kNumberRoom + 2);
        for (int k = 0; k < 3; ++k) {
            if (k > 0) cursor.put(' ');
            cursor.number(r.xyz[k]);
        }
    });
    out.append(text.substr(replacements.empty() ? 0 : replacements.back().end));
}

// A name as the last word of a line: one that ends in a backslash gets a blank after it, or the reader
// would take the backslash for a line continuation.
std::string lineEndName(const std::string& name) {
    return !name.empty() && name.back() == '\\' ? name + " " : name;
}

bool isSingleToken(const std::string& s) {
    if (s.empty()) return false;
    for (char c : s)
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\0') return false;
    return true;
}

}  // namespace

Status checkObjMesh(const ObjMesh& mesh) {
    auto bad = [](const std::string& what) { return Status::error("invalid OBJ mesh: " + what); };
    const long long vertexCount = mesh.positions.rows();
    const long long texcoordCount = mesh.texcoords.rows();
    if (mesh.faceStart.empty() || mesh.faceStart[0] != 0) return bad("faceStart must start with 0");
    const size_t faceCount = mesh.faceStart.size() - 1;
    const size_t cornerCount = mesh.cornerVertex.size();
    if (static_cast<size_t>(mesh.faceStart.back()) != cornerCount) return bad("faceStart must end at the corner count");
    if (mesh.cornerTexcoord.size() != cornerCount || mesh.cornerNormal.size() != cornerCount)
        return bad("corner arrays differ in size");
    if (mesh.faceGroup.size() != faceCount || mesh.faceMaterial.size() != faceCount)
        return bad("per-face arrays differ from the face count");
    for (size_t f = 0; f < faceCount; ++f)
        if (mesh.faceStart[f + 1] - mesh.faceStart[f] < 3) return bad("face " + std::to_string(f) + " has < 3 corners");
    for (size_t c = 0; c < cornerCount; ++c) {
        if (mesh.cornerVertex[c] < 0 || mesh.cornerVertex[c] >= vertexCount) return bad("corner vertex out of range");
        if (mesh.cornerTexcoord[c] < -1 || mesh.cornerTexcoord[c] >= texcoordCount)
            return bad("corner texture coordinate out of range");
    }
    if (texcoordCount > 0 && mesh.texcoords.cols() != 2 && mesh.texcoords.cols() != 3)
        return bad("texcoords must have 2 or 3 columns");
    if (!mesh.texcoords.allFinite()) return bad("non-finite texture coordinate");
    if (mesh.triangles.size() > 0 && (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= vertexCount))
        return bad("triangle index out of range");
    if (mesh.triangleFace.size() != static_cast<size_t>(mesh.triangles.rows()))
        return bad("triangleFace differs from the triangle count");
    if (mesh.groupNames.empty() || !mesh.groupNames[0].empty()) return bad("groupNames[0] must be the unnamed group");
    for (int g : mesh.faceGroup)
        if (g < 0 || static_cast<size_t>(g) >= mesh.groupNames.size()) return bad("face group out of range");
    for (int m : mesh.faceMaterial)
        if (m < -1 || m >= static_cast<long long>(mesh.materialNames.size())) return bad("face material out of range");
    for (const std::string& name : mesh.groupNames)
        if (hasLineBreak(name)) return bad("group name with a line break");
    for (const std::string& name : mesh.materialNames)
        if (!isSingleToken(name)) return bad("material name '" + name + "' must be one word");
    for (const std::string& name : mesh.materialLibraries)
        if (name.empty() || hasLineBreak(name)) return bad("empty material library name or one with a line break");
    if (mesh.vertexColors.rows() != 0 && mesh.vertexColors.rows() != vertexCount)
        return bad("vertexColors must have 0 or one row per vertex");
    if (mesh.vertexNormals.rows() != 0 && mesh.vertexNormals.rows() != vertexCount)
        return bad("vertexNormals must have 0 or one row per vertex");
    if (!mesh.vertexColors.allFinite() || !mesh.vertexNormals.allFinite()) return bad("non-finite vertex colour or normal");
    if (mesh.source) {
        const ObjSource& source = *mesh.source;
        if (source.positionSpans.size() != 2 * static_cast<size_t>(vertexCount))
            return bad("the source text's vertex count differs from the positions");
        if (!spansAreOrdered(source.positionSpans, source.text.size()) ||
            !spansAreOrdered(source.normalSpans, source.text.size()) ||
            !spansAreDisjoint(source.positionSpans, source.normalSpans))
            return bad("the source text's number spans are out of order");
        const long long normalCount = static_cast<long long>(source.normalSpans.size() / 2);
        for (int n : mesh.cornerNormal)
            if (n < -1 || n >= normalCount) return bad("corner normal out of range of the source's normals");
    }
    return Status::success();
}

Status serializeObj(const ObjMesh& mesh, const Positions& deformedPositions, std::string& text) {
    try {
        Status status = checkObjMesh(mesh);
        if (!status) return status;
        if (deformedPositions.rows() != mesh.positions.rows())
            return Status::error("cannot write OBJ: " + std::to_string(deformedPositions.rows()) +
                                 " positions for a mesh with " + std::to_string(mesh.positions.rows()) + " vertices");
        for (Eigen::Index v = 0; v < deformedPositions.rows(); ++v)
            if (!deformedPositions.row(v).allFinite())
                return Status::error("cannot write OBJ: vertex " + std::to_string(v + 1) +
                                     " has a non-finite position");

        std::string out;
        if (mesh.source) {
            writeFromSource(mesh, deformedPositions, out);
            text.swap(out);
            return Status::success();
        }

        Positions normals;
        core::computeVertexNormals(deformedPositions, mesh.triangles, normals);

        // ~24 bytes per number, ~12 per corner index triple: one allocation for typical meshes.
        reserveWithHugePages(out, static_cast<size_t>(deformedPositions.rows()) * 150 + mesh.cornerVertex.size() * 24 +
                                      static_cast<size_t>(mesh.texcoords.size()) * 25 + 256);
        out += "# DMFFD Sculpt\n";
        for (const std::string& library : mesh.materialLibraries) out += "mtllib " + lineEndName(library) + "\n";
        // Room for a whole line is made at its start: 6 numbers and their separators at most (a `v` with colours).
        constexpr size_t kLineRoom = 8 * TextCursor::kNumberRoom;
        appendRowsInParallel(out, deformedPositions.rows(), [&](Eigen::Index v, TextCursor& line) {
            line.room(kLineRoom);
            line.put('v');
            for (int k = 0; k < 3; ++k) {
                line.put(' ');
                line.number(deformedPositions(v, k));
            }
            // Vertex colours (from a PLY or glTF file) as the common `v x y z r g b` extension (0..1).
            for (Eigen::Index k = 0; k < 3 && mesh.vertexColors.rows() > 0; ++k) {
                line.put(' ');
                line.number(mesh.vertexColors(v, k));  // a float
            }
            line.put('\n');
        });
        appendRowsInParallel(out, mesh.texcoords.rows(), [&](Eigen::Index t, TextCursor& line) {
            line.room(kLineRoom);
            line.put('v');
            line.put('t');
            for (Eigen::Index k = 0; k < mesh.texcoords.cols(); ++k) {
                line.put(' ');
                line.number(mesh.texcoords(t, k));
            }
            line.put('\n');
        });
        appendRowsInParallel(out, normals.rows(), [&](Eigen::Index v, TextCursor& line) {
            // computeVertexNormals promises finite unit normals; a NaN here would make the file unreadable.
            const bool finite = normals.row(v).allFinite();
            line.room(kLineRoom);
            line.put('v');
            line.put('n');
            for (int k = 0; k < 3; ++k) {
                line.put(' ');
                line.number(finite ? normals(v, k) : (k == 2 ? 1.0 : 0.0));
            }
            line.put('\n');
        });
        // A `g` or `usemtl` line comes before a face whose group or material differs from the face before it
        // (the unnamed group 0 and no material before the first face): each face's lines depend on it and the
        // one before only, so the faces format in parallel too.
        appendRowsInParallel(out, mesh.faceCount(), [&](Eigen::Index face, TextCursor& line) {
            const int f = static_cast<int>(face);
            if (mesh.faceGroup[f] != (f > 0 ? mesh.faceGroup[f - 1] : 0))
                // note: "g " with a trailing blank is the unnamed group; a bare "g" is not a group line
                // to tinyobjloader and would be ignored.
                line.put("g " + lineEndName(mesh.groupNames[mesh.faceGroup[f]]) + "\n");
            const int material = mesh.faceMaterial[f];
            if (material != (f > 0 ? mesh.faceMaterial[f - 1] : -1))
                line.put(material < 0 ? std::string("usemtl\n") : "usemtl " + lineEndName(mesh.materialNames[material]) + "\n");
            line.room(2);
            line.put('f');
            for (int c = mesh.faceStart[f]; c < mesh.faceStart[f + 1]; ++c) {
                const long long vertex = mesh.cornerVertex[c] + 1LL;
                line.room(4 + 3 * TextCursor::kNumberRoom);  // " v/t/n" of one corner
                line.put(' ');
                line.number(vertex);
                line.put('/');
                if (mesh.cornerTexcoord[c] >= 0) line.number(mesh.cornerTexcoord[c] + 1LL);
                line.put('/');
                line.number(vertex);  // one recomputed normal per vertex
            }
            line.room(1);
            line.put('\n');
        });
        text.swap(out);
        return Status::success();
    } catch (const std::bad_alloc&) {
        return Status::error("cannot write OBJ: not enough memory");
    }
}

Status saveObj(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions) {
    try {
        std::string text;
        Status status = serializeObj(mesh, deformedPositions, text);
        if (!status) return Status::error(path + ": " + status.message);
        return writeFileAtomically(path, text);
    } catch (const std::bad_alloc&) {
        return Status::error(path + ": not enough memory to save");
    }
}

}  // namespace sculpt::io
