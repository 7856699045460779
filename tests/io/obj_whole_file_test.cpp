// Every file the OBJ format allows opens, and what it holds is written back: line continuations, faces of
// any size, vertex colours, `l`/`p`/`vp`/`s` and other statements. Round trips go through the engine: load,
// drag (core::Session), save, load again; the saved text is checked with a statement splitter of this
// test's own, independent of the reader.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "io/script.h"
#include "core/session/session.h"
#include "io/obj_mesh.h"
#include "io/script_json.h"
#include "io_test_support.h"
#include "obj_test_support.h"

using sculpt::Positions;
using sculpt::Status;
using sculpt::io::ObjMesh;

namespace {

const std::string kDataDir = std::string(SCULPT_SOURCE_DIR) + "/tests/io/data";

Status loadText(const std::string& text, ObjMesh& mesh, std::vector<std::string>* warnings = nullptr) {
    return sculpt::io::loadObjFromText(text, "test.obj", "", mesh, warnings);
}

ObjMesh requireLoad(const std::string& text, std::vector<std::string>* warnings = nullptr) {
    ObjMesh mesh;
    const Status status = loadText(text, mesh, warnings);
    INFO(status.message);
    REQUIRE(status.ok);
    REQUIRE(sculpt::io::checkObjMesh(mesh).ok);
    return mesh;
}

bool anyContains(const std::vector<std::string>& lines, const std::string& fragment) {
    for (const std::string& line : lines)
        if (line.find(fragment) != std::string::npos) return true;
    return false;
}

std::string withLineEnds(std::string text, const std::string& lineEnd) {
    std::string out;
    for (char c : text) {
        if (c == '\n')
            out += lineEnd;
        else
            out += c;
    }
    return out;
}

// The statements of an OBJ text as the format defines them, written here from the specification and not
// shared with the reader: a backslash ending a line joins it with the next, lines end at LF, CR LF or CR,
// tokens are separated by blanks. Comment lines are statements too (keyword "#"), so comments are compared.
std::vector<std::vector<std::string>> statements(const std::string& text) {
    std::vector<std::string> lines;
    std::string current;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\r' || c == '\n') {
            if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
            // A backslash right before the line break continues the statement.
            if (!current.empty() && current.back() == '\\') {
                current.back() = ' ';
                continue;
            }
            lines.push_back(current);
            current.clear();
        } else {
            current += c;
        }
    }
    if (!current.empty() && current.back() == '\\') current.pop_back();  // continued onto the end of the file
    lines.push_back(current);
    std::vector<std::vector<std::string>> out;
    for (const std::string& line : lines) {
        std::vector<std::string> tokens;
        size_t at = 0;
        while (at < line.size()) {
            at = line.find_first_not_of(" \t", at);
            if (at == std::string::npos) break;
            const size_t stop = line.find_first_of(" \t", at);
            tokens.push_back(line.substr(at, stop - at));
            at = stop == std::string::npos ? line.size() : stop;
        }
        if (!tokens.empty()) out.push_back(tokens);
    }
    return out;
}

// Checks that `saved` holds the same statements as `original`, in the same order and with the same tokens,
// except the x y z of `v` lines (which must read as `positions`) and the numbers of `vn` lines.
void requireSameStatements(const std::string& original, const std::string& saved, const Positions& positions) {
    const auto before = statements(original), after = statements(saved);
    REQUIRE(before.size() == after.size());
    Eigen::Index vertex = 0;
    for (size_t s = 0; s < before.size(); ++s) {
        INFO("statement " << s << ": " << before[s][0]);
        REQUIRE(before[s].size() == after[s].size());
        REQUIRE(before[s][0] == after[s][0]);
        if (before[s][0] == "v") {
            for (int k = 0; k < 3; ++k) REQUIRE(std::stod(after[s][static_cast<size_t>(k + 1)]) == positions(vertex, k));
            for (size_t t = 4; t < before[s].size(); ++t) REQUIRE(before[s][t] == after[s][t]);  // w, colours
            ++vertex;
        } else if (before[s][0] != "vn") {
            REQUIRE(before[s] == after[s]);
        }
    }
    REQUIRE(vertex == positions.rows());
}

// The given vertex dragged by `offset` through the engine, as the window does; returns the new positions.
Positions dragVertex(const ObjMesh& mesh, int vertex, const Eigen::Vector3d& offset) {
    sculpt::core::Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
    sculpt::core::OpReport report;
    const Eigen::Vector3d target = mesh.positions.row(vertex).transpose() + offset;
    REQUIRE(session.dragVertex(vertex, target, report).ok);
    INFO(report.reason);
    REQUIRE(report.status == sculpt::core::OpStatus::Applied);
    REQUIRE((session.mesh().positions.row(vertex).transpose() - target).norm() < 1e-9);
    return session.mesh().positions;
}

std::string serialize(const ObjMesh& mesh, const Positions& positions) {
    std::string text;
    const Status status = sculpt::io::serializeObj(mesh, positions, text);
    INFO(status.message);
    REQUIRE(status.ok);
    return text;
}

bool sameBits(const Positions& a, const Positions& b) {
    return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

// Drags one vertex, saves, reloads: the same faces and attributes, the dragged positions bit for bit, and
// every statement of `original` in order with only the moved numbers changed.
void requireDragRoundTrip(const ObjMesh& mesh, const std::string& original, int vertex, const Eigen::Vector3d& offset) {
    const Positions dragged = dragVertex(mesh, vertex, offset);
    const std::string saved = serialize(mesh, dragged);
    const ObjMesh reread = requireLoad(saved);
    sculpt::test::requireSameFaces(mesh, reread);
    REQUIRE(sameBits(reread.positions, dragged));
    requireSameStatements(original, saved, dragged);
}

double triangleArea(const ObjMesh& mesh, Eigen::Index t, const Eigen::Vector3d& normal) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(t, 2)).transpose();
    return 0.5 * (b - a).cross(c - a).dot(normal);
}

}  // namespace

TEST_CASE("obj: the handed-over cube with continued v, vn and f lines loads whole and its drag lands") {
    const std::string path = kDataDir + "/cases/line_continuation.obj";
    const std::string original = sculpt::test::readBytes(path);
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const Status loaded = sculpt::io::loadObj(path, mesh, &warnings);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    REQUIRE(mesh.vertexCount() == 8);
    REQUIRE(mesh.faceCount() == 6);
    REQUIRE(mesh.positions.row(5) == Eigen::RowVector3d(1, 0, 1));  // vertex 6, continued over two lines
    REQUIRE(mesh.cornerNormal == std::vector<int>(24, 0));           // the one continued `vn`
    REQUIRE(mesh.triangles.rows() == 12);

    sculpt::io::Script script;
    const Status read = sculpt::io::loadScript(kDataDir + "/cases/line_continuation.json", script);
    INFO(read.message);
    REQUIRE(read.ok);
    sculpt::core::Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, script.lattice).ok);
    session.setInjectivity(script.injectivity);
    sculpt::io::ScriptReport report;
    const Status ran = sculpt::io::runScript(session, script, report);
    INFO(ran.message);
    REQUIRE(ran.ok);
    REQUIRE(report.ops.size() == 1);
    REQUIRE(report.ops[0].status == sculpt::core::OpStatus::Applied);
    REQUIRE((session.mesh().positions.row(6) - Eigen::RowVector3d(1.2, 1.2, 1.2)).norm() < 1e-9);

    // Saved and loaded again: the same cube, the continued face line kept as it was.
    const std::string saved = serialize(mesh, session.mesh().positions);
    REQUIRE(saved.find("f 5//1 6//1 \\\n   7//1 8//1\n") != std::string::npos);
    const ObjMesh reread = requireLoad(saved);
    sculpt::test::requireSameFaces(mesh, reread);
    REQUIRE(sameBits(reread.positions, session.mesh().positions));
    requireSameStatements(original, saved, session.mesh().positions);
}

TEST_CASE("obj: a backslash continues any kind of line, with LF, CR LF or CR line ends, up to the end of file") {
    // Every statement continued at least once; two continuations in a row; a continuation onto an empty
    // line; the last line continued with no line end after it.
    const std::string text =
        "# a comment that goes on \\\n"
        "and on\n"
        "mtllib \\\n"
        " shop.mtl\n"
        "o \\\n"
        " thing\n"
        "v 0 0 0\n"
        "v 1 \\\n"
        " 0 0\n"
        "v 1 1 0 \\\n"
        "\n"
        "v 0 1 0 0.25 \\\n"
        "0.5 \\\n"
        "0.75\n"
        "vt 0.5 \\\n"
        " 0.25\n"
        "vn 0 0 \\\n"
        " 1\n"
        "vp 0.5 \\\n"
        " 0.5\n"
        "g two \\\n"
        " words\n"
        "usemtl \\\n"
        " red\n"
        "s \\\n"
        " 1\n"
        "f 1/1/1 2/1/1 \\\n"
        " 3/1/1 \\\n"
        " 4/1/1\n"
        "l 1 \\\n"
        " 2\n"
        "p \\\n"
        " 3\n"
        "f 1 2 \\\n"
        "3 \\";
    for (const std::string lineEnd : {"\n", "\r\n", "\r"}) {
        INFO("line end " << (lineEnd == "\n" ? "LF" : lineEnd == "\r\n" ? "CR LF" : "CR"));
        const std::string file = withLineEnds(text, lineEnd);
        std::vector<std::string> warnings;
        const ObjMesh mesh = requireLoad(file, &warnings);
        REQUIRE(mesh.vertexCount() == 4);
        Positions expected(4, 3);
        expected << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
        REQUIRE(mesh.positions == expected);
        REQUIRE(mesh.faceStart == std::vector<int>{0, 4, 7});
        REQUIRE(mesh.cornerVertex == std::vector<int>{0, 1, 2, 3, 0, 1, 2});
        REQUIRE(mesh.cornerTexcoord == std::vector<int>{0, 0, 0, 0, -1, -1, -1});
        REQUIRE(mesh.cornerNormal == std::vector<int>{0, 0, 0, 0, -1, -1, -1});
        REQUIRE(mesh.texcoords.rows() == 1);
        REQUIRE(mesh.texcoords.row(0) == Eigen::RowVector2d(0.5, 0.25));
        REQUIRE(mesh.groupNames == std::vector<std::string>{"", "two words"});
        REQUIRE(mesh.materialNames == std::vector<std::string>{"red"});
        REQUIRE(mesh.materialLibraries == std::vector<std::string>{"shop.mtl"});
        REQUIRE(anyContains(warnings, "2 line/point element(s) not shown, kept in the file (first on line 30)"));
        REQUIRE(anyContains(warnings, "statement(s) the sculptor does not use, kept in the file (first on line 19: 'vp')"));

        // Unchanged, the file is written back byte for byte; dragged, only the moved numbers change.
        REQUIRE(serialize(mesh, mesh.positions) == file);
        requireDragRoundTrip(mesh, file, 2, {0.1, 0.2, 0.3});
    }
}

TEST_CASE("obj: errors in and after continued lines name the line the statement starts on") {
    struct Case {
        std::string text;
        std::string where;
        std::string what;
    };
    const Case cases[] = {
        {"v 0 0 0\nv 1 \\\n 0 0\nv 0 x 0\nf 1 2 3\n", "test.obj:4: ", "'x' in a 'v' line"},
        {"v 0 0 0\nv 1 \\\n 0 \\\n nan\nv 0 1 0\nf 1 2 3\n", "test.obj:2: ", "'nan' in a 'v' line"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n 2 \\\n 9\n", "test.obj:4: ", "face index 9 is out of range"},
        {"v 0 0 0\r\nv 1 \\\r\n 0 0\r\nv 0 1 0\r\nf 1 2\r\n", "test.obj:5: ", "a face needs at least 3 corners (found 2)"},
        // A backslash inside a line, or followed by blanks, is no continuation.
        {"v 0 \\ 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "test.obj:1: ", "'\\' in a 'v' line"},
        {"v 0 0 0\nv 1 0 \\ \n0\nv 0 1 0\nf 1 2 3\n", "test.obj:2: ", "'\\' in a 'v' line"},
    };
    for (const Case& c : cases) {
        INFO(c.text);
        ObjMesh mesh;
        const Status status = loadText(c.text, mesh);
        INFO(status.message);
        REQUIRE_FALSE(status.ok);
        REQUIRE(status.message.find(c.where + c.what) != std::string::npos);
    }
}

TEST_CASE("obj: faces of any size load, are triangulated exactly and written back whole") {
    for (int corners : {256, 1000, 20000}) {
        INFO(corners << " corners");
        // A star-shaped (concave) polygon between a triangle and a quad, in groups, so the faces tinyobjloader
        // does not see are skipped in the right place.
        std::mt19937_64 random(static_cast<unsigned>(corners));
        std::uniform_real_distribution<double> radius(0.4, 1.0);
        std::string text = "v 0 0 5\nv 1 0 5\nv 0 1 5\nv 1 1 5\ng small\nf 1 2 3\ng big\no  big \n";
        std::vector<Eigen::Vector2d> flat;
        for (int i = 0; i < corners; ++i) {
            const double angle = 2.0 * 3.14159265358979323846 * i / corners, r = radius(random);
            flat.emplace_back(r * std::cos(angle), r * std::sin(angle));
            char line[96];
            std::snprintf(line, sizeof line, "v %.17g %.17g 0\n", flat.back().x(), flat.back().y());
            text += line;
        }
        text += "f";
        for (int i = 0; i < corners; ++i) text += " " + std::to_string(i + 5);
        text += "\ng small\nf 2 4 3\n";
        std::vector<std::string> warnings;
        const ObjMesh mesh = requireLoad(text, &warnings);
        for (const std::string& w : warnings) UNSCOPED_INFO(w);
        REQUIRE(warnings.empty());
        REQUIRE(mesh.faceStart == std::vector<int>{0, 3, 3 + corners, 6 + corners});
        REQUIRE(mesh.faceGroup == std::vector<int>{1, 2, 1});
        REQUIRE(mesh.faceMaterial == std::vector<int>{-1, -1, -1});
        REQUIRE(mesh.triangles.rows() == 1 + (corners - 2) + 1);
        // The polygon's triangles: facing +z and adding up to its shoelace area.
        double shoelace = 0.0;
        for (size_t i = 0; i < flat.size(); ++i) {
            const Eigen::Vector2d& a = flat[i];
            const Eigen::Vector2d& b = flat[(i + 1) % flat.size()];
            shoelace += 0.5 * (a.x() * b.y() - a.y() * b.x());
        }
        double sum = 0.0;
        for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
            if (mesh.triangleFace[static_cast<size_t>(t)] != 1) continue;
            const double area = triangleArea(mesh, t, Eigen::Vector3d::UnitZ());
            REQUIRE(area > 0.0);
            sum += area;
        }
        REQUIRE(sum == Approx(shoelace).epsilon(1e-12));

        requireDragRoundTrip(mesh, text, 4 + corners / 3, {0.0, 0.0, 0.05});
    }
}

TEST_CASE("obj: vertex colours, w, texture coordinates and every other statement survive load, drag, save, load") {
    // A 4 x 4 grid of quads as a scanner would write it: colours on every vertex, plus one vertex with a w,
    // normals per vertex, and statements the sculptor does not use, all of which must come back in order.
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::string text = "# scanned with care\nmtllib scan.mtl\no scan\n";
    char line[160];
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            if (i == 2 && j == 2) {
                text += "v 0.5 0.5 0.0 1.0\n";  // x y z w
                continue;
            }
            std::snprintf(line, sizeof line, "v %.3f %.3f %.3f %.6f %.6f %.6f\n", i * 0.25, j * 0.25,
                          0.1 * unit(random), unit(random), unit(random), unit(random));
            text += line;
        }
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            std::snprintf(line, sizeof line, "vt %g %g\n", i * 0.25, j * 0.25);
            text += line;
        }
    for (int v = 0; v < 25; ++v) text += "vn 0 0 1\n";
    text += "vp 0.25 0.5\nvp 0.75 0.5 1\ncstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\n";
    text += "s 1\ng surface\nusemtl clay\n";
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const int a = j * 5 + i + 1, b = a + 1, c = a + 6, d = a + 5;
            std::snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, b, b, b, c, c, c, d, d, d);
            text += line;
            if (i == 1 && j == 1) text += "s off\n";
        }
    text += "l 1 2 3 4 5\nl -1/-1 -2/-2\np 13\nmg 1 0.5\n# the end\n";

    std::vector<std::string> warnings;
    const ObjMesh mesh = requireLoad(text, &warnings);
    REQUIRE(mesh.vertexCount() == 25);
    REQUIRE(mesh.faceCount() == 16);
    REQUIRE(anyContains(warnings, "3 line/point element(s) not shown, kept in the file"));
    REQUIRE(anyContains(warnings, "statement(s) the sculptor does not use, kept in the file"));

    const Positions dragged = dragVertex(mesh, 12, {0.0, 0.0, 0.3});
    REQUIRE((dragged - mesh.positions).rowwise().norm().maxCoeff() > 0.2);
    const std::string saved = serialize(mesh, dragged);
    const ObjMesh reread = requireLoad(saved);
    sculpt::test::requireSameFaces(mesh, reread);
    REQUIRE(sameBits(reread.positions, dragged));
    REQUIRE(reread.triangles == mesh.triangles);
    REQUIRE(reread.source->normalSpans.size() == mesh.source->normalSpans.size());
    // Same statements in the same order; on every `v` line the colours (or the w) as they were.
    requireSameStatements(text, saved, dragged);
    const auto savedStatements = statements(saved);
    int coloured = 0;
    for (const auto& statement : savedStatements) coloured += statement[0] == "v" && statement.size() == 7;
    REQUIRE(coloured == 24);
    // Saved again from what was read: nothing drifts.
    REQUIRE(serialize(reread, reread.positions) == saved);
}

TEST_CASE("obj: a mesh saved unchanged is the file it was loaded from, byte for byte") {
    for (const char* name : {"valid_polygons.obj", "valid_relative.obj", "cases/line_continuation.obj",
                             "cases/concave_u.obj"}) {
        INFO(name);
        ObjMesh mesh;
        REQUIRE(sculpt::io::loadObj(kDataDir + "/" + name, mesh).ok);
        REQUIRE(serialize(mesh, mesh.positions) == sculpt::test::readBytes(kDataDir + "/" + name));
    }
    // With a byte order mark too.
    const std::string bom = "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    REQUIRE(serialize(requireLoad(bom), requireLoad(bom).positions) == bom);
}

TEST_CASE("obj: normals of faces that changed shape are recomputed, the others stay as written") {
    // Two separate quads with one normal per vertex, written unnormalised, and a cube-like hard edge: quad C
    // shares one normal among its four corners.
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "v 3 0 0\nv 4 0 0\nv 4 1 0\nv 3 1 0\n"
        "v 6 0 0\nv 7 0 0\nv 7 1 0\nv 6 1 0\n"
        "vn 0 0 2\nvn 0 0 2\nvn 0 0 2\nvn 0 0 2\n"
        "vn 0 0 3.0\nvn 0 0 3.0\nvn 0 0 3.0\nvn 0 0 3.0\n"
        "vn 0.0 0.0 1.0\n"
        "f 1//1 2//2 3//3 4//4\nf 5//5 6//6 7//7 8//8\nf 9//9 10//9 11//9 12//9\n";
    const ObjMesh mesh = requireLoad(text);
    // Quad A stood up into the xz plane, (x, y, 0) -> (x, 0, y): its normal becomes (0, -1, 0). Quad C lifted
    // (moved, normal direction unchanged). Quad B untouched.
    Positions deformed = mesh.positions;
    for (int v = 0; v < 4; ++v) {
        deformed(v, 2) = deformed(v, 1);
        deformed(v, 1) = 0.0;
    }
    for (int v = 8; v < 12; ++v) deformed(v, 2) += 0.5;
    const std::string saved = serialize(mesh, deformed);
    std::vector<std::vector<std::string>> normals;
    for (const auto& statement : statements(saved))
        if (statement[0] == "vn") normals.push_back(statement);
    REQUIRE(normals.size() == 9);
    const auto value = [&](int n) {
        const auto& statement = normals[static_cast<size_t>(n)];
        REQUIRE(statement.size() == 4);
        return Eigen::Vector3d(std::stod(statement[1]), std::stod(statement[2]), std::stod(statement[3]));
    };
    for (int n = 0; n < 4; ++n) REQUIRE(value(n) == Eigen::Vector3d(0, -1, 0));
    for (int n = 4; n < 8; ++n) REQUIRE(normals[static_cast<size_t>(n)] == std::vector<std::string>{"vn", "0", "0", "3.0"});
    REQUIRE(normals[8] == std::vector<std::string>{"vn", "0", "0", "1"});  // recomputed: moved, now unit length
    const ObjMesh reread = requireLoad(saved);
    REQUIRE(sameBits(reread.positions, deformed));
    sculpt::test::requireSameFaces(mesh, reread);
}

TEST_CASE("obj: the handed-over concave U is triangulated inside the U and saved as its one face") {
    const std::string path = kDataDir + "/cases/concave_u.obj";
    ObjMesh mesh;
    std::vector<std::string> warnings;
    REQUIRE(sculpt::io::loadObj(path, mesh, &warnings).ok);
    REQUIRE(warnings.empty());
    REQUIRE(mesh.faceStart == std::vector<int>{0, 8});
    REQUIRE(mesh.triangles.rows() == 6);
    double area = 0.0;
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        const double a = triangleArea(mesh, t, Eigen::Vector3d::UnitZ());
        REQUIRE(a > 0.0);  // all facing +z, the face's winding
        area += a;
        // No triangle reaches into the notch (1 < x < 2, 1 < y < 3): its centroid is outside it.
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) centroid += mesh.positions.row(mesh.triangles(t, k)).transpose() / 3.0;
        REQUIRE_FALSE((centroid.x() > 1.0 && centroid.x() < 2.0 && centroid.y() > 1.0));
    }
    REQUIRE(area == Approx(7.0).epsilon(1e-15));
    // The engine takes the same triangles; after a drag the file still holds the one 8-corner face.
    const Positions dragged = dragVertex(mesh, 2, {0.2, 0.1, 0.0});
    const std::string saved = serialize(mesh, dragged);
    REQUIRE(saved.find("f 1 2 3 4 5 6 7 8\n") != std::string::npos);
    const ObjMesh reread = requireLoad(saved);
    REQUIRE(reread.faceStart == std::vector<int>{0, 8});
    REQUIRE(sameBits(reread.positions, dragged));
}

TEST_CASE("obj: non-planar, collinear and degenerate polygons: exact where possible, else a fan and a warning") {
    SECTION("a non-planar concave hexagon is covered, every triangle facing along its normal") {
        // An L-shaped hexagon with its corners lifted alternately.
        const ObjMesh mesh =
            requireLoad("v 0 0 0\nv 2 0 0.1\nv 2 1 0\nv 1 1 0.1\nv 1 2 0\nv 0 2 0.1\nf 1 2 3 4 5 6\n");
        REQUIRE(mesh.triangles.rows() == 4);
        double area = 0.0;
        for (Eigen::Index t = 0; t < 4; ++t) {
            const double a = triangleArea(mesh, t, Eigen::Vector3d::UnitZ());
            REQUIRE(a > 0.0);
            area += a;
        }
        REQUIRE(area == Approx(3.0).epsilon(1e-12));
    }
    SECTION("corners on a straight edge give no degenerate triangle") {
        const ObjMesh mesh = requireLoad("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nv 0 1 0\nf 1 2 3 4 5 6\n");
        REQUIRE(mesh.triangles.rows() == 4);
        for (Eigen::Index t = 0; t < 4; ++t) REQUIRE(triangleArea(mesh, t, Eigen::Vector3d::UnitZ()) > 0.0);
    }
    SECTION("faces that cannot be triangulated load as a fan, with a warning naming the first one") {
        std::vector<std::string> warnings;
        const ObjMesh mesh = requireLoad(
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 2 1 0\nv 0 1 0\nv -1 0.5 0\n"
            "f 1 2 3\n"
            "f 1 2 3 4\n"      // all corners on one line
            "f 1 5 3 6 7\n",  // crosses itself
            &warnings);
        for (const std::string& w : warnings) UNSCOPED_INFO(w);
        REQUIRE(anyContains(warnings, "test.obj: 2 face(s) could not be triangulated exactly and are drawn as a fan "
                                      "of their corners (first on line 9: the polygon has zero area"));
        REQUIRE(mesh.triangles.rows() == 1 + 2 + 3);
        REQUIRE(mesh.triangles.row(1) == Eigen::RowVector3i(0, 1, 2));
        REQUIRE(mesh.triangles.row(2) == Eigen::RowVector3i(0, 2, 3));
        // The engine and the writer take it: finite normals, a file that loads again.
        sculpt::core::Session session;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
        Positions moved = mesh.positions;
        moved(0, 2) = 0.25;
        const ObjMesh reread = requireLoad(serialize(mesh, moved));
        REQUIRE(reread.positions.allFinite());
        sculpt::test::requireSameFaces(mesh, reread);
    }
}

TEST_CASE("obj: a big loaded file's save rewrites exactly the moved vertices' numbers, in parallel chunks") {
    // Over 32768 replacements the save formats chunks of the source text in parallel (obj_write.cpp): every
    // statement must still be the source's own except the moved vertices' positions and the recomputed normals.
    std::mt19937 rng(12345);
    constexpr int kRows = 200, kColumns = 250;  // a grid of quads: 50,000 vertices, v and vn lines interleaved
    std::string text = "# a big grid\nmtllib none.mtl\n";
    for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kColumns; ++c)
            text += "v " + std::to_string(c) + " " + std::to_string(r) + " 0.5\nvn 0 0 1\nvt 0.25 0.75\n";
    text += "g sheet\n";
    for (int r = 0; r + 1 < kRows; ++r)
        for (int c = 0; c + 1 < kColumns; ++c) {
            const int a = r * kColumns + c + 1, b = a + 1, d = a + kColumns, e = d + 1;
            text += "f " + std::to_string(a) + "/" + std::to_string(a) + "/" + std::to_string(a) + " " + std::to_string(b) + "/" +
                    std::to_string(b) + "/" + std::to_string(b) + " " + std::to_string(e) + "/" + std::to_string(e) + "/" +
                    std::to_string(e) + " " + std::to_string(d) + "/" + std::to_string(d) + "/" + std::to_string(d) + "\n";
        }
    const ObjMesh mesh = requireLoad(text);
    const auto source = statements(text);
    for (const double fraction : {0.02, 0.4, 1.0}) {
        INFO("moved fraction " << fraction);
        Positions deformed = mesh.positions;
        std::vector<char> moved(static_cast<size_t>(deformed.rows()), 0);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (Eigen::Index v = 0; v < deformed.rows(); ++v)
            if (unit(rng) < fraction) {
                moved[static_cast<size_t>(v)] = 1;
                deformed(v, 2) += 0.1 + unit(rng) / 3.0;  // a bump: the grid's normals change where it moves
            }
        const std::string saved = serialize(mesh, deformed);
        const auto written = statements(saved);
        REQUIRE(written.size() == source.size());
        size_t vertex = 0, changedNormals = 0;
        for (size_t i = 0; i < source.size(); ++i) {
            if (source[i][0] == "v") {
                REQUIRE(written[i].size() == 4);
                if (moved[vertex]) {
                    for (int k = 0; k < 3; ++k)
                        REQUIRE(std::stod(written[i][size_t(k) + 1]) == deformed(static_cast<Eigen::Index>(vertex), k));
                } else {
                    REQUIRE(written[i] == source[i]);
                }
                ++vertex;
            } else if (source[i][0] == "vn" && written[i] != source[i]) {
                REQUIRE(written[i].size() == 4);
                const Eigen::Vector3d n(std::stod(written[i][1]), std::stod(written[i][2]), std::stod(written[i][3]));
                REQUIRE(std::abs(n.norm() - 1.0) < 1e-12);
                ++changedNormals;
            } else {
                REQUIRE(written[i] == source[i]);
            }
        }
        CHECK(changedNormals > 0);
        const ObjMesh reread = requireLoad(saved);
        REQUIRE(sameBits(reread.positions, deformed));
        sculpt::test::requireSameFaces(mesh, reread);
    }
}
