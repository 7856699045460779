// OFF reading and writing (off_mesh.h).
#include "io/off_mesh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cctype>
#include <cstring>
#include <string_view>

#include "io/load_checks.h"

namespace sculpt::io {

namespace {

// The file as lines of numbers: each call to next() gives the next line that holds anything but blanks and
// a comment, split into its tokens, with its 1-based number.
class OffLines {
public:
    explicit OffLines(const std::string& bytes) : bytes_(bytes) {}
    bool next(std::vector<std::string_view>& tokens, long long& line) {
        tokens.clear();
        while (at_ < bytes_.size() && tokens.empty()) {
            size_t end = bytes_.find('\n', at_);
            if (end == std::string::npos) end = bytes_.size();
            ++line_;
            const void* comment = std::memchr(bytes_.data() + at_, '#', end - at_);
            const size_t stop = comment ? static_cast<size_t>(static_cast<const char*>(comment) - bytes_.data()) : end;
            for (size_t c = at_; c < stop;) {
                if (std::isspace(static_cast<unsigned char>(bytes_[c]))) {
                    ++c;
                    continue;
                }
                const size_t first = c;
                while (c < stop && !std::isspace(static_cast<unsigned char>(bytes_[c]))) ++c;
                tokens.emplace_back(bytes_.data() + first, c - first);
            }
            at_ = end + 1;
        }
        line = line_;
        return !tokens.empty();
    }

private:
    const std::string& bytes_;
    size_t at_ = 0;
    long long line_ = 0;
};

bool parseOffNumber(std::string_view token, double& out) {
    const char* first = token.data();
    if (!token.empty() && token[0] == '+') ++first;
    const auto [end, error] = std::from_chars(first, token.data() + token.size(), out);
    return error == std::errc() && end == token.data() + token.size() && std::isfinite(out);
}

bool parseOffIndex(std::string_view token, long long& out) {
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), out);
    return error == std::errc() && end == token.data() + token.size();
}

}  // namespace

Status readOffDocument(const std::string& bytes, const std::string& name, ObjMesh& out, std::vector<std::string>& notes) {
    OffLines lines(bytes);
    std::vector<std::string_view> tokens;
    long long line = 0;
    const auto fail = [&](const std::string& what) { return Status::error(name + ": line " + std::to_string(line) + ": " + what); };
    if (!lines.next(tokens, line)) return Status::error(name + ": not an OFF file (it holds no header)");
    // The header keyword, [ST][C][N][4]OFF (Geomview's order), then the counts on its line or the next.
    std::string_view keyword = tokens[0];
    const auto take = [&keyword](std::string_view prefix) {
        if (keyword.substr(0, prefix.size()) != prefix) return false;
        keyword.remove_prefix(prefix.size());
        return true;
    };
    const bool textures = take("ST"), colours = take("C"), normals = take("N"), homogeneous = take("4");
    if (keyword == "nOFF") return fail("nOFF (a dimension other than 3) is not read");
    if (keyword != "OFF")
        return fail("not an OFF file (it starts with '" + std::string(tokens[0].substr(0, 40)) + "', not OFF, COFF, NOFF, CNOFF or 4OFF)");
    size_t next = 1;
    if (next < tokens.size() && tokens[next] == "BINARY") return fail("binary OFF is not read (save it as ASCII OFF)");
    if (next >= tokens.size()) {
        if (!lines.next(tokens, line)) return fail("the file ends after its header (no vertex and face counts)");
        next = 0;
    }
    long long vertexCount = -1, faceCount = -1;
    if (tokens.size() < next + 2 || !parseOffIndex(tokens[next], vertexCount) || !parseOffIndex(tokens[next + 1], faceCount) ||
        vertexCount < 0 || faceCount < 0)
        return fail("the counts line must give the numbers of vertices and faces (and edges), as whole numbers");
    // Each vertex takes at least 6 bytes ("0 0 0\n"), each face 2 ("0\n"): a count beyond that is a file cut
    // short or a damaged header, refused before anything is sized by it.
    if (vertexCount > static_cast<long long>(bytes.size() / 6) || faceCount > static_cast<long long>(bytes.size() / 2))
        return fail("the header declares " + std::to_string(vertexCount) + " vertices and " + std::to_string(faceCount) +
                    " faces, more than the file's " + std::to_string(bytes.size()) + " bytes can hold (truncated?)");
    if (Status s = checkVertexTotal(name, static_cast<size_t>(vertexCount)); !s) return s;

    ObjMesh mesh;
    mesh.groupNames = {std::string()};
    const Eigen::Index n = static_cast<Eigen::Index>(vertexCount);
    mesh.positions.resize(n, 3);
    if (normals) mesh.vertexNormals.resize(n, 3);
    if (textures) mesh.texcoords.resize(n, 2);
    VertexColors vertexColours;
    if (colours) vertexColours = VertexColors::Ones(n, 4);
    const int coordinates = homogeneous ? 4 : 3;
    const int fixed = coordinates + (normals ? coordinates : 0) + (textures ? 2 : 0);
    bool anyColour = false;
    std::vector<double> numbers;
    for (Eigen::Index v = 0; v < n; ++v) {
        if (!lines.next(tokens, line))
            return Status::error(name + ": the file ends early: its header declares " + std::to_string(vertexCount) +
                                 " vertices, and it ends after " + std::to_string(v) + " (truncated?)");
        numbers.resize(tokens.size());
        for (size_t t = 0; t < tokens.size(); ++t)
            if (!parseOffNumber(tokens[t], numbers[t]))
                return fail("vertex " + std::to_string(v) + ": '" + std::string(tokens[t].substr(0, 40)) + "' is not a finite number");
        // The colour entries lie between the normal and the texture coordinates: 0, 3 (RGB) or 4 (RGBA).
        const long long colourEntries = static_cast<long long>(numbers.size()) - fixed;
        if (colourEntries < 0 || (!colours && colourEntries > 0) || colourEntries == 1 || colourEntries == 2 || colourEntries > 4)
            return fail("vertex " + std::to_string(v) + " has " + std::to_string(numbers.size()) + " numbers; each vertex of this " +
                        std::string(textures ? "ST" : "") + (colours ? "C" : "") + (normals ? "N" : "") +
                        (homogeneous ? "4" : "") + "OFF has " + std::to_string(fixed) +
                        (colours ? (", then 3 or 4 for its colour" + std::string(colourEntries == 1 ? " (colour map indices are not read)" : ""))
                                 : std::string()));
        const double w = homogeneous ? numbers[3] : 1.0;
        if (w == 0.0) return fail("vertex " + std::to_string(v) + " has w = 0 (a point at infinity)");
        mesh.positions.row(v) << numbers[0] / w, numbers[1] / w, numbers[2] / w;
        if (!mesh.positions.row(v).allFinite()) return fail("vertex " + std::to_string(v) + " is not finite");
        size_t at = static_cast<size_t>(coordinates);
        if (normals) {
            mesh.vertexNormals.row(v) << static_cast<float>(numbers[at]), static_cast<float>(numbers[at + 1]), static_cast<float>(numbers[at + 2]);
            at += static_cast<size_t>(coordinates);
        }
        if (colourEntries > 0) {
            // Written as integers ("255 128 0"), as MeshLab and CGAL write them: 0-255; with a point or an
            // exponent ("1.0 0.5 0"): 0-1. (CGAL's scanner decides by value, so it reads "1.0 0 0" as nearly black.)
            const bool bytesScale = std::all_of(tokens.begin() + static_cast<std::ptrdiff_t>(at), tokens.begin() + static_cast<std::ptrdiff_t>(at) + 3,
                                                [](std::string_view c) { return c.find_first_of(".eE") == std::string_view::npos; });
            const double scale = bytesScale ? 255.0 : 1.0;
            for (long long k = 0; k < colourEntries; ++k) {
                const double c = numbers[at + static_cast<size_t>(k)];
                if (c < 0.0 || c > scale)
                    return fail("vertex " + std::to_string(v) + ": colour " + std::string(tokens[at + static_cast<size_t>(k)].substr(0, 40)) +
                                " is outside " + (bytesScale ? "0-255" : "0-1"));
                vertexColours(v, static_cast<Eigen::Index>(k)) = static_cast<float>(c / scale);
            }
            anyColour = true;
            at += static_cast<size_t>(colourEntries);
        }
        if (textures) mesh.texcoords.row(v) << numbers[at], numbers[at + 1];
    }
    if (anyColour) mesh.vertexColors = vertexColours;
    mesh.faceStart.push_back(0);
    long long small = 0, faceColours = 0;
    for (long long f = 0; f < faceCount; ++f) {
        if (!lines.next(tokens, line))
            return Status::error(name + ": the file ends early: its header declares " + std::to_string(faceCount) +
                                 " faces, and it ends after " + std::to_string(f) + " (truncated?)");
        long long corners = -1;
        if (!parseOffIndex(tokens[0], corners) || corners < 0)
            return fail("face " + std::to_string(f) + ": '" + std::string(tokens[0].substr(0, 40)) + "' is not a vertex count");
        if (static_cast<long long>(tokens.size()) - 1 < corners)
            return fail("face " + std::to_string(f) + " declares " + std::to_string(corners) + " vertices and lists " +
                        std::to_string(tokens.size() - 1));
        const long long extra = static_cast<long long>(tokens.size()) - 1 - corners;
        if (extra != 0 && extra != 1 && extra != 3 && extra != 4)
            return fail("face " + std::to_string(f) + " has " + std::to_string(extra) + " numbers after its " + std::to_string(corners) +
                        " vertex indices (a face colour is 1, 3 or 4)");
        for (size_t t = static_cast<size_t>(corners) + 1; t < tokens.size(); ++t) {
            double unused = 0.0;
            if (!parseOffNumber(tokens[t], unused))
                return fail("face " + std::to_string(f) + ": '" + std::string(tokens[t].substr(0, 40)) + "' is not a number");
        }
        faceColours += extra > 0;
        if (corners < 3) {
            ++small;
            continue;
        }
        for (long long c = 1; c <= corners; ++c) {
            long long index = -1;
            if (!parseOffIndex(tokens[static_cast<size_t>(c)], index) || index < 0 || index >= vertexCount)
                return fail("face " + std::to_string(f) + ": '" + std::string(tokens[static_cast<size_t>(c)].substr(0, 40)) +
                            "' is not a vertex index (0 to " + std::to_string(vertexCount - 1) + ")");
            mesh.cornerVertex.push_back(static_cast<int>(index));
            mesh.cornerTexcoord.push_back(textures ? static_cast<int>(index) : -1);
            mesh.cornerNormal.push_back(-1);
        }
        mesh.faceStart.push_back(static_cast<int>(mesh.cornerVertex.size()));
        mesh.faceGroup.push_back(0);
        mesh.faceMaterial.push_back(-1);
    }
    // Anything after the last face is named: nothing is dropped in silence.
    long long leftover = 0, firstLeftover = 0;
    while (lines.next(tokens, line)) {
        if (leftover == 0) firstLeftover = line;
        ++leftover;
    }
    if (leftover > 0)
        notes.push_back(std::to_string(leftover) + " line(s) after the last face the header declares (from line " +
                        std::to_string(firstLeftover) + ") are not read");
    if (mesh.faceCount() == 0) return noSurfaceError(name, false, static_cast<size_t>(n));
    if (small > 0) notes.push_back(std::to_string(small) + " face(s) of fewer than 3 vertices (points, edges) are not kept");
    if (faceColours > 0) notes.push_back("face colours are not kept (" + std::to_string(faceColours) + " faces had one)");
    if (colours && !anyColour) notes.push_back("the header says COFF, but no vertex has a colour");
    out = std::move(mesh);
    return Status::success();
}

std::string writeOff(const ObjMesh& mesh, const Positions& deformed, const VertexColors& colours, const VertexNormals& normals) {
    const bool withColours = colours.rows() == deformed.rows() && colours.rows() > 0;
    const bool withNormals = normals.rows() == deformed.rows() && normals.rows() > 0;
    std::string out = std::string(withColours ? "C" : "") + (withNormals ? "N" : "") + "OFF\n# DMFFD Sculpt\n";
    out += std::to_string(deformed.rows()) + " " + std::to_string(mesh.faceCount()) + " 0\n";
    char number[40];
    // Integers 0-255 when every colour is one (what was read from such a file, or 8-bit colours), else 0-1.
    bool colourBytes = true;
    for (Eigen::Index v = 0; v < colours.rows() && withColours && colourBytes; ++v)
        for (int k = 0; k < 4; ++k) {
            const float c = std::clamp(colours(v, k), 0.0f, 1.0f);
            colourBytes &= static_cast<float>(std::lround(c * 255.0) / 255.0) == c;
        }
    // std::to_chars: the shortest text that reads back to the same double, whatever the locale (as obj_write.cpp).
    const auto put = [&](double x) -> std::string_view {
        const size_t length = static_cast<size_t>(std::to_chars(number, number + sizeof number, x).ptr - number);
        out.append(number, length);
        return std::string_view(number, length);
    };
    for (Eigen::Index v = 0; v < deformed.rows(); ++v) {
        for (int k = 0; k < 3; ++k) {
            if (k > 0) out += ' ';
            put(deformed(v, k));
        }
        for (int k = 0; k < 3 && withNormals; ++k) {
            out += ' ';
            put(static_cast<double>(normals(v, k)));
        }
        for (int k = 0; k < 4 && withColours; ++k) {
            const double c = std::clamp(static_cast<double>(colours(v, k)), 0.0, 1.0);
            if (colourBytes) {
                out += ' ' + std::to_string(std::lround(c * 255.0));
            } else {
                // 0-1, with a point so it reads back on that scale (readOffDocument's rule).
                out += ' ';
                if (put(c).find_first_of(".e") == std::string_view::npos) out += ".0";
            }
        }
        out += '\n';
    }
    for (int f = 0; f < mesh.faceCount(); ++f) {
        out += std::to_string(mesh.faceStart[static_cast<size_t>(f) + 1] - mesh.faceStart[static_cast<size_t>(f)]);
        for (int c = mesh.faceStart[static_cast<size_t>(f)]; c < mesh.faceStart[static_cast<size_t>(f) + 1]; ++c)
            out += ' ' + std::to_string(mesh.cornerVertex[static_cast<size_t>(c)]);
        out += '\n';
    }
    return out;
}

}  // namespace sculpt::io
