// make_default_mesh [output.obj]   (default: assets/default.obj, relative to the working folder)
//
// Generates the mesh the app opens with: a level-5 subdivided icosahedron (10242 vertices, 20480
// triangles) shaped into a slightly squashed blob with a few soft bumps, with spherical UVs and one
// group, written through saveObj. The shape is a radial graph r(d) * d over the unit sphere followed
// by a linear stretch; with r > 0 and smooth that is an embedding, so the surface is closed, manifold
// and free of self-intersections (tests/io/obj_default_mesh_test.cpp checks all of it on the file).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "io/obj_mesh.h"

namespace {

using Vec3 = std::array<double, 3>;

constexpr int kSubdivisions = 5;  // 20 * 4^5 = 20480 triangles: smooth to sculpt, light for llvmpipe
constexpr double kPi = 3.14159265358979323846;

Vec3 normalized(const Vec3& v) {
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return {v[0] / length, v[1] / length, v[2] / length};
}

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct Sphere {
    std::vector<Vec3> directions;           // unit vectors
    std::vector<std::array<int, 3>> faces;  // counter-clockwise seen from outside
};

Sphere icosphere(int subdivisions) {
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    Sphere sphere;
    for (const Vec3& v : std::vector<Vec3>{{-1, phi, 0},
                                           {1, phi, 0},
                                           {-1, -phi, 0},
                                           {1, -phi, 0},
                                           {0, -1, phi},
                                           {0, 1, phi},
                                           {0, -1, -phi},
                                           {0, 1, -phi},
                                           {phi, 0, -1},
                                           {phi, 0, 1},
                                           {-phi, 0, -1},
                                           {-phi, 0, 1}})
        sphere.directions.push_back(normalized(v));
    sphere.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int level = 0; level < subdivisions; ++level) {
        std::map<std::pair<int, int>, int> midpoints;  // shared edge -> its new vertex, so edges weld
        auto midpoint = [&](int a, int b) {
            const std::pair<int, int> key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
            const auto found = midpoints.find(key);
            if (found != midpoints.end()) return found->second;
            const Vec3& p = sphere.directions[a];
            const Vec3& q = sphere.directions[b];
            sphere.directions.push_back(normalized({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
            const int index = static_cast<int>(sphere.directions.size()) - 1;
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<std::array<int, 3>> finer;
        finer.reserve(sphere.faces.size() * 4);
        for (const auto& f : sphere.faces) {
            const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
            finer.push_back({f[0], ab, ca});
            finer.push_back({f[1], bc, ab});
            finer.push_back({f[2], ca, bc});
            finer.push_back({ab, bc, ca});
        }
        sphere.faces.swap(finer);
    }
    return sphere;
}

// Radius over the unit sphere: 1 plus a few Gaussian-like bumps exp(-(1 - d.c) / width). Smooth and
// well above 0, so the radial graph stays an embedding.
double blobRadius(const Vec3& d) {
    struct Bump {
        Vec3 centre;
        double height, width;
    };
    static const Bump bumps[] = {
        {normalized({0.3, 0.8, 0.5}), 0.16, 0.10},   {normalized({-0.7, 0.2, 0.6}), 0.12, 0.07},
        {normalized({0.6, -0.3, -0.7}), 0.14, 0.09}, {normalized({-0.4, -0.6, -0.5}), 0.10, 0.06},
        {normalized({0.9, 0.1, -0.2}), 0.09, 0.05},
    };
    double r = 1.0;
    for (const Bump& bump : bumps) r += bump.height * std::exp(-(1.0 - dot(d, bump.centre)) / bump.width);
    // A gentle low-frequency wobble so the blob is not too regular.
    r += 0.03 * std::sin(3.0 * d[0] + 1.0) * std::cos(2.0 * d[2]);
    return r;
}

// note: positions are rounded to 1e-6 before writing so the shortest round-trip text is short
// ("0.512345" rather than 17 digits): the asset stays well under 3 MB, and the rounding (< 1e-6) is
// tiny next to the ~0.03 edge length.
double rounded(double x) { return std::round(x * 1e6) / 1e6; }

}  // namespace

int main(int argc, char** argv) {
    const std::string output = argc > 1 ? argv[1] : "assets/default.obj";
    const Sphere sphere = icosphere(kSubdivisions);
    const int vertexCount = static_cast<int>(sphere.directions.size());
    const int faceCount = static_cast<int>(sphere.faces.size());

    sculpt::io::ObjMesh mesh;
    mesh.positions.resize(vertexCount, 3);
    const Vec3 stretch = {1.12, 0.82, 1.0};  // slightly squashed vertically, a little wider in x
    for (int v = 0; v < vertexCount; ++v) {
        const Vec3& d = sphere.directions[v];
        const double r = blobRadius(d);
        for (int k = 0; k < 3; ++k) mesh.positions(v, k) = rounded(stretch[k] * r * d[k]);
    }

    // Spherical UVs from the undeformed direction, per corner: a triangle straddling the seam gets
    // u + 1 on its small-u corners, and a pole corner takes the mean u of the other two, so no
    // triangle is stretched across the whole texture. Equal (u, v) pairs share one `vt`.
    std::map<std::pair<double, double>, int> texcoordIndex;
    std::vector<std::pair<double, double>> texcoords;
    auto addTexcoord = [&](double u, double v) {
        const std::pair<double, double> key(rounded(u), rounded(v));
        const auto inserted = texcoordIndex.emplace(key, static_cast<int>(texcoords.size()));
        if (inserted.second) texcoords.push_back(key);
        return inserted.first->second;
    };

    mesh.faceStart.push_back(0);
    mesh.triangles.resize(faceCount, 3);
    for (int f = 0; f < faceCount; ++f) {
        const auto& face = sphere.faces[f];
        double u[3], v[3];
        bool pole[3];
        for (int c = 0; c < 3; ++c) {
            const Vec3& d = sphere.directions[face[c]];
            pole[c] = d[0] * d[0] + d[2] * d[2] < 1e-12;
            u[c] = pole[c] ? 0.0 : 0.5 + std::atan2(d[2], d[0]) / (2.0 * kPi);
            v[c] = 0.5 + std::asin(std::max(-1.0, std::min(1.0, d[1]))) / kPi;
        }
        double uMin = 2.0, uMax = -1.0;
        for (int c = 0; c < 3; ++c)
            if (!pole[c]) uMin = std::min(uMin, u[c]), uMax = std::max(uMax, u[c]);
        for (int c = 0; c < 3; ++c)
            if (!pole[c] && uMax - uMin > 0.5 && u[c] < 0.5) u[c] += 1.0;
        for (int c = 0; c < 3; ++c) {
            if (!pole[c]) continue;
            double sum = 0.0;
            int count = 0;
            for (int o = 0; o < 3; ++o)
                if (!pole[o]) sum += u[o], ++count;
            u[c] = count > 0 ? sum / count : 0.5;
        }
        for (int c = 0; c < 3; ++c) {
            mesh.cornerVertex.push_back(face[c]);
            mesh.cornerTexcoord.push_back(addTexcoord(u[c], v[c]));
            mesh.cornerNormal.push_back(-1);
            mesh.triangles(f, c) = face[c];
        }
        mesh.faceStart.push_back(static_cast<int>(mesh.cornerVertex.size()));
        mesh.triangleFace.push_back(f);
        mesh.faceGroup.push_back(1);
        mesh.faceMaterial.push_back(-1);
    }
    mesh.texcoords.resize(static_cast<Eigen::Index>(texcoords.size()), 2);
    for (size_t t = 0; t < texcoords.size(); ++t)
        mesh.texcoords.row(static_cast<Eigen::Index>(t)) << texcoords[t].first, texcoords[t].second;
    mesh.groupNames = {"", "blob"};

    const sculpt::Status status = sculpt::io::saveObj(output, mesh, mesh.positions);
    if (!status) {
        std::fprintf(stderr, "make_default_mesh: %s\n", status.message.c_str());
        return 1;
    }
    std::printf("make_default_mesh: wrote %s (%d vertices, %d triangles, %zu texture coordinates)\n", output.c_str(),
                vertexCount, faceCount, texcoords.size());
    return 0;
}
