// Lattice tools as JSON: predefined shapes and explicit nets (lattice_json.h).
#include "io/lattice_json.h"

#include <algorithm>
#include <stdexcept>

#include "core/volume/composite_volume.h"
#include "core/tspline/tspline_volume.h"
#include "io/atomic_file.h"
#include "io/json_fields.h"
#include "io/json_text.h"
#include "io/script_json.h"

namespace sculpt::io {

using namespace json_fields;

namespace {

void check(const Status& status, const std::string& path) {
    if (!status) fail(path, status.message);
}

Eigen::Matrix3d edgesOf(const json& j, const std::string& path) {
    if (!j.is_array() || j.size() != 3) fail(path, "expected 3 edge vectors [[x,y,z], [x,y,z], [x,y,z]]");
    Eigen::Matrix3d edges;
    for (int a = 0; a < 3; ++a) edges.col(a) = vector3(j[a], path + "[" + std::to_string(a) + "]");
    return edges;
}

core::PlanarNet parseProfile(const json& j, const std::string& path) {
    allowOnly(j, path, {"min", "max", "chunks", "degree", "points"});
    const std::array<int, 2> chunks = intArray<2>(required(j, "chunks", path), path + ".chunks");
    const std::array<int, 2> degree = j.contains("degree") ? intArray<2>(j["degree"], path + ".degree") : std::array<int, 2>{2, 2};
    for (int a = 0; a < 2; ++a) {
        if (degree[a] < core::kMinDegree || degree[a] > core::kMaxDegree) fail(path + ".degree", "expected degrees in [1, 5]");
        if (chunks[a] < 1 || chunks[a] + degree[a] > core::kMaxControlPointsPerAxis) fail(path + ".chunks", "expected 1 or more chunks (at most 64 points per axis)");
    }
    const Eigen::Vector2d lo = vector2(required(j, "min", path), path + ".min"), hi = vector2(required(j, "max", path), path + ".max");
    if (!(lo.array() < hi.array()).all()) fail(path, "min must be below max on both axes");
    core::PlanarNet net = core::makeRectangleNet(lo, hi, chunks, degree);
    if (j.contains("points")) {  // the 2D lattice's points moved by hand (row u fastest)
        const json& points = j["points"];
        if (!points.is_array() || points.size() != net.points.size())
            fail(path + ".points", "expected " + std::to_string(net.points.size()) + " [u,v] points");
        for (size_t p = 0; p < points.size(); ++p) net.points[p] = vector2(points[p], path + ".points[" + std::to_string(p) + "]");
    }
    return net;
}

// A loft section: the profile placed by hand, {"origin", "u_axis", "v_axis", "scale"} (world point = origin +
// scale_u p_u u + scale_v p_v v, u and v orthonormalised as an extrusion's), or its count_u x count_v world
// points [[x,y,z], ...] (row u fastest).
Positions parseSection(const json& j, const std::string& path, const core::PlanarNet& profile) {
    const size_t perSection = profile.points.size();
    Positions section(static_cast<Eigen::Index>(perSection), 3);
    if (j.is_array()) {
        if (j.size() != perSection) fail(path, "expected " + std::to_string(perSection) + " [x,y,z] points (the profile's count_u x count_v)");
        for (size_t p = 0; p < perSection; ++p)
            section.row(static_cast<Eigen::Index>(p)) = vector3(j[p], path + "[" + std::to_string(p) + "]").transpose();
        return section;
    }
    if (!j.is_object()) fail(path, "expected a placement {\"origin\", \"u_axis\", \"v_axis\", \"scale\"} or an array of [x,y,z] points");
    allowOnly(j, path, {"origin", "u_axis", "v_axis", "scale"});
    const Eigen::Vector3d origin = vector3(required(j, "origin", path), path + ".origin");
    const Eigen::Vector3d uAxis = j.contains("u_axis") ? vector3(j["u_axis"], path + ".u_axis") : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d vAxis = j.contains("v_axis") ? vector3(j["v_axis"], path + ".v_axis") : Eigen::Vector3d::UnitY();
    Eigen::Vector2d scale(1.0, 1.0);
    if (j.contains("scale")) {
        const json& sj = j["scale"];
        scale = sj.is_array() ? vector2(sj, path + ".scale") : Eigen::Vector2d::Constant(number(sj, path + ".scale"));
        if (!(scale.array() > 0.0).all()) fail(path + ".scale", "expected a scale > 0 (or [u, v] scales > 0)");
    }
    const Eigen::Vector3d u = uAxis.normalized();
    const Eigen::Vector3d v = (vAxis - vAxis.dot(u) * u).normalized();
    if (!(uAxis.norm() > 0.0) || !u.allFinite() || !v.allFinite() || !(u.cross(vAxis).norm() > 1e-12 * vAxis.norm()))
        fail(path, "u_axis and v_axis must be non-zero and not parallel");
    for (size_t p = 0; p < perSection; ++p)
        section.row(static_cast<Eigen::Index>(p)) =
            (origin + scale.x() * profile.points[p].x() * u + scale.y() * profile.points[p].y() * v).transpose();
    return section;
}

core::LatticeNet parseNet(const json& j, const std::string& path) {
    if (!j.is_object()) fail(path, "expected a lattice object");
    const std::string kind = text(required(j, "kind", path), path + ".kind");
    core::LatticeNet net;
    if (kind == "parallelepiped") {
        allowOnly(j, path, {"kind", "origin", "edges", "chunks", "degree"});
        const std::array<int, 3> degree = j.contains("degree") ? int3(j["degree"], path + ".degree") : std::array<int, 3>{3, 3, 3};
        check(core::makeParallelepipedNet(vector3(required(j, "origin", path), path + ".origin"), edgesOf(required(j, "edges", path), path + ".edges"),
                                          int3(required(j, "chunks", path), path + ".chunks"), degree, net),
              path);
    } else if (kind == "cylinder") {
        allowOnly(j, path, {"kind", "base", "axis", "radius", "height", "chunks", "degree"});
        const std::array<int, 2> degree = j.contains("degree") ? intArray<2>(j["degree"], path + ".degree") : std::array<int, 2>{2, 2};
        check(core::makeCylinderNet(vector3(required(j, "base", path), path + ".base"), vector3(required(j, "axis", path), path + ".axis"),
                                    number(required(j, "radius", path), path + ".radius"), number(required(j, "height", path), path + ".height"),
                                    int3(required(j, "chunks", path), path + ".chunks"), degree, net),
              path);
    } else if (kind == "sphere") {
        allowOnly(j, path, {"kind", "centre", "axis", "radius", "chunks", "degree"});
        const Eigen::Vector3d axis = j.contains("axis") ? vector3(j["axis"], path + ".axis") : Eigen::Vector3d::UnitZ();
        check(core::makeSphereNet(vector3(required(j, "centre", path), path + ".centre"), axis, number(required(j, "radius", path), path + ".radius"),
                                  int3(required(j, "chunks", path), path + ".chunks"), j.contains("degree") ? integer(j["degree"], path + ".degree") : 2, net),
              path);
    } else if (kind == "prism") {
        allowOnly(j, path, {"kind", "profile", "origin", "u_axis", "v_axis", "direction", "chunks", "degree"});
        const core::PlanarNet profile = parseProfile(required(j, "profile", path), path + ".profile");
        check(core::makeExtrusionNet(profile, vector3(required(j, "origin", path), path + ".origin"),
                                     j.contains("u_axis") ? vector3(j["u_axis"], path + ".u_axis") : Eigen::Vector3d::UnitX(),
                                     j.contains("v_axis") ? vector3(j["v_axis"], path + ".v_axis") : Eigen::Vector3d::UnitY(),
                                     vector3(required(j, "direction", path), path + ".direction"),
                                     j.contains("chunks") ? integer(j["chunks"], path + ".chunks") : 1,
                                     j.contains("degree") ? integer(j["degree"], path + ".degree") : 1, net),
              path);
    } else if (kind == "loft") {
        allowOnly(j, path, {"kind", "profile", "sections", "degree"});
        const core::PlanarNet profile = parseProfile(required(j, "profile", path), path + ".profile");
        const json& sections = required(j, "sections", path);
        if (!sections.is_array()) fail(path + ".sections", "expected an array of sections");
        std::vector<Positions> placed;
        for (size_t k = 0; k < sections.size(); ++k)
            placed.push_back(parseSection(sections[k], path + ".sections[" + std::to_string(k) + "]", profile));
        check(core::makeLoftNet(profile, placed, j.contains("degree") ? integer(j["degree"], path + ".degree") : 2, net), path);
    } else if (kind == "net") {
        allowOnly(j, path, {"kind", "shape", "count", "degree", "multiplicity", "knots", "points", "weights", "welds"});
        if (j.contains("shape")) net.kind = text(j["shape"], path + ".shape");
        net.count = int3(required(j, "count", path), path + ".count");
        net.degree = int3(required(j, "degree", path), path + ".degree");
        net.multiplicity = j.contains("multiplicity") ? int3(j["multiplicity"], path + ".multiplicity") : std::array<int, 3>{1, 1, 1};
        if (j.contains("knots")) {
            // Per axis a clamped knot vector, or [] for the uniform knots of count, degree and multiplicity.
            const json& knots = j["knots"];
            if (!knots.is_array() || knots.size() != 3) fail(path + ".knots", "expected 3 knot vectors ([] for uniform knots)");
            for (int a = 0; a < 3; ++a) {
                const std::string kp = path + ".knots[" + std::to_string(a) + "]";
                if (!knots[static_cast<size_t>(a)].is_array()) fail(kp, "expected an array of knots");
                for (size_t k = 0; k < knots[static_cast<size_t>(a)].size(); ++k)
                    net.knots[static_cast<size_t>(a)].push_back(number(knots[static_cast<size_t>(a)][k], kp + "[" + std::to_string(k) + "]"));
                if (net.knots[static_cast<size_t>(a)].empty()) continue;
                if (const std::string problem = core::splineKnotsProblem(net.knots[static_cast<size_t>(a)], net.count[a], net.degree[a]);
                    !problem.empty())
                    fail(kp, problem);
            }
        }
        for (int a = 0; a < 3; ++a)
            if (net.knots[static_cast<size_t>(a)].empty() && !core::splineAxisCountValid(net.count[a], net.degree[a], net.multiplicity[a]))
                fail(path + ".count", "axis " + std::to_string(a) + ": " + std::to_string(net.count[a]) + " points of degree " +
                                          std::to_string(net.degree[a]) + " and knot multiplicity " + std::to_string(net.multiplicity[a]) +
                                          " do not make whole knot spans (degree 1-5, multiplicity 1-degree, at most 64 points)");
        const json& points = required(j, "points", path);
        const size_t n = static_cast<size_t>(net.count[0]) * net.count[1] * net.count[2];
        if (!points.is_array() || points.size() != n) fail(path + ".points", "expected " + std::to_string(n) + " [x,y,z] points (count's product)");
        net.rest.resize(static_cast<Eigen::Index>(n), 3);
        for (size_t p = 0; p < n; ++p) net.rest.row(static_cast<Eigen::Index>(p)) = vector3(points[p], path + ".points[" + std::to_string(p) + "]").transpose();
        if (j.contains("weights")) {
            const json& weights = j["weights"];
            if (!weights.is_array() || weights.size() != n) fail(path + ".weights", "expected " + std::to_string(n) + " weights");
            for (size_t p = 0; p < n; ++p) {
                const double w = number(weights[p], path + ".weights[" + std::to_string(p) + "]");
                if (!(w > 0.0)) fail(path + ".weights[" + std::to_string(p) + "]", "expected a weight > 0");
                net.weights.push_back(w);
            }
        }
        net.weldedTo.resize(n);
        for (size_t p = 0; p < n; ++p) net.weldedTo[p] = static_cast<int>(p);
        if (j.contains("welds")) {
            const json& welds = j["welds"];
            if (!welds.is_array()) fail(path + ".welds", "expected an array of groups of control point ids");
            for (size_t g = 0; g < welds.size(); ++g) {
                const std::string gp = path + ".welds[" + std::to_string(g) + "]";
                if (!welds[g].is_array() || welds[g].size() < 2) fail(gp, "expected a group of 2 or more control point ids");
                int smallest = static_cast<int>(n);
                std::vector<int> group;
                for (size_t m = 0; m < welds[g].size(); ++m) {
                    const int id = integer(welds[g][m], gp + "[" + std::to_string(m) + "]");
                    if (id < 0 || id >= static_cast<int>(n)) fail(gp + "[" + std::to_string(m) + "]", "control point id outside the lattice");
                    if (net.weldedTo[id] != id) fail(gp + "[" + std::to_string(m) + "]", "control point is already in another weld group");
                    group.push_back(id);
                    smallest = std::min(smallest, id);
                }
                for (int id : group) net.weldedTo[id] = smallest;
            }
        }
        check(core::finishLatticeNet(net), path);
    } else {
        fail(path + ".kind", "unknown lattice kind \"" + kind + "\" (known: parallelepiped, cylinder, sphere, prism, loft, net)");
    }
    return net;
}

}  // namespace

Status parseLatticeNetJson(const json& j, const std::string& path, core::LatticeNet& out) {
    try {
        out = parseNet(j, path);
    } catch (const FieldError& e) {
        return Status::error(e.path + ": " + e.what);
    }
    return Status::success();
}

json latticeNetJson(const core::LatticeNet& net) {
    json points = json::array();
    for (Eigen::Index p = 0; p < net.rest.rows(); ++p) points.push_back(vectorJson(net.rest.row(p).transpose()));
    json welds = json::array();
    for (const auto& group : net.weldGroups) welds.push_back(group);
    json out = {{"kind", "net"},    {"shape", net.kind},      {"count", net.count}, {"degree", net.degree}, {"multiplicity", net.multiplicity},
                {"points", points}, {"weights", net.weights}, {"welds", welds}};
    // General knot vectors (knot insertion at a chosen parameter) only; uniform axes are [] there.
    if (std::any_of(net.knots.begin(), net.knots.end(), [](const std::vector<double>& k) { return !k.empty(); }))
        out["knots"] = net.knots;
    return out;
}

Status parseLatticeFile(const std::string& content, const std::string& displayName, LatticeFile& out) {
    json j;
    if (Status s = parseJsonText(content, displayName, j); !s) return s;
    LatticeFile file;
    try {
        allowOnly(j, "", {"format", "version", "name", "lattice"});
        if (text(required(j, "format", ""), ".format") != "dmffd-lattice") fail(".format", "expected \"dmffd-lattice\"");
        if (integer(required(j, "version", ""), ".version") != 1) fail(".version", "expected 1");
        file.name = j.contains("name") ? json_fields::text(j["name"], ".name") : std::string("lattice");
        if (Status s = parseVolumeJson(required(j, "lattice", ""), "lattice", file.volume); !s) {
            const size_t colon = s.message.find(": ");  // "field.path: what"
            fail(s.message.substr(0, colon), colon == std::string::npos ? s.message : s.message.substr(colon + 2));
        }
    } catch (const FieldError& e) {
        return Status::error(displayName + ": " + e.path + ": " + e.what);
    }
    out = std::move(file);
    return Status::success();
}

Status readLatticeFile(const std::string& path, LatticeFile& out) {
    std::string content;
    if (Status s = readTextFile(path, content); !s) return s;
    return parseLatticeFile(content, path, out);
}

std::string latticeFileText(const LatticeFile& file) {
    const json j = {{"format", "dmffd-lattice"}, {"version", 1}, {"name", file.name}, {"lattice", volumeJson(*file.volume)}};
    return j.dump(1) + "\n";
}

Status writeLatticeFile(const std::string& path, const LatticeFile& file) { return writeFileAtomically(path, latticeFileText(file)); }

namespace {

// A weighted T-spline volume (Song & Yang 2005; core/tspline/tspline_volume.h): {"kind": "tspline", "root": [Ru, Rv, Rw],
// "root_knots": [[0, .., 1] x 3] (optional; absent or [] = uniform along that axis), "cells": [[level, i, j, k], ...] (the T-lattice's
// octree leaves), "points": [[x,y,z], ...] and "weights": [...] (one per anchor, in the volume's id order)}.
VolumeFormat tsplineVolumeFormat() {
    VolumeFormat format;
    format.kinds = {"tspline"};
    format.read = [](const json& j, const std::string& path, std::shared_ptr<const core::Volume>& out) {
        try {
            allowOnly(j, path, {"kind", "root", "root_knots", "cells", "points", "weights"});
            core::TLattice lattice;
            lattice.rootCount = int3(required(j, "root", path), path + ".root");
            if (j.contains("root_knots")) {
                const json& knots = j["root_knots"];
                if (!knots.is_array() || knots.size() != 3) fail(path + ".root_knots", "expected 3 arrays of knot values");
                for (size_t a = 0; a < 3; ++a) {
                    const std::string kp = path + ".root_knots[" + std::to_string(a) + "]";
                    if (!knots[a].is_array()) fail(kp, "expected an array of knot values");
                    for (size_t i = 0; i < knots[a].size(); ++i) lattice.rootKnots[a].push_back(number(knots[a][i], kp + "[" + std::to_string(i) + "]"));
                }
            }
            const json& cells = required(j, "cells", path);
            if (!cells.is_array() || cells.empty()) fail(path + ".cells", "expected an array of cells [level, i, j, k]");
            for (size_t c = 0; c < cells.size(); ++c) {
                const std::array<int, 4> cell = intArray<4>(cells[c], path + ".cells[" + std::to_string(c) + "]");
                lattice.cells.push_back(core::TLatticeCell{cell[0], {cell[1], cell[2], cell[3]}});
            }
            std::shared_ptr<const core::TSplineBasis> basis;
            if (Status s = core::buildTSplineBasis(lattice, basis); !s) fail(path + ".cells", s.message);
            const size_t n = static_cast<size_t>(basis->anchorCount());
            const json& points = required(j, "points", path);
            if (!points.is_array() || points.size() != n) fail(path + ".points", "expected " + std::to_string(n) + " [x,y,z] points (one per anchor)");
            Positions rest(static_cast<Eigen::Index>(n), 3);
            for (size_t p = 0; p < n; ++p) rest.row(static_cast<Eigen::Index>(p)) = vector3(points[p], path + ".points[" + std::to_string(p) + "]").transpose();
            std::vector<double> weights(n, 1.0);
            if (j.contains("weights")) {
                const json& w = j["weights"];
                if (!w.is_array() || w.size() != n) fail(path + ".weights", "expected " + std::to_string(n) + " weights");
                for (size_t p = 0; p < n; ++p) {
                    weights[p] = number(w[p], path + ".weights[" + std::to_string(p) + "]");
                    if (!(weights[p] > 0.0)) fail(path + ".weights[" + std::to_string(p) + "]", "expected a weight > 0");
                }
            }
            std::shared_ptr<const core::TSplineVolume> made;
            if (Status s = core::TSplineVolume::make(std::move(basis), std::move(rest), std::move(weights), made); !s) fail(path, s.message);
            out = std::move(made);
        } catch (const FieldError& e) {
            return Status::error(e.path + ": " + e.what);
        }
        return Status::success();
    };
    format.write = [](const core::Volume& volume, json& out) {
        const core::TSplineVolume* made = volume.tsplineVolume();
        if (!made) return false;
        const core::TLattice& lattice = made->lattice();
        json cells = json::array();
        for (const auto& cell : lattice.cells) cells.push_back({cell.level, cell.index[0], cell.index[1], cell.index[2]});
        json points = json::array();
        for (Eigen::Index p = 0; p < made->restControlPoints().rows(); ++p) points.push_back(vectorJson(made->restControlPoints().row(p).transpose()));
        out = {{"kind", "tspline"}, {"root", lattice.rootCount}, {"cells", cells}, {"points", points}, {"weights", made->controlWeights()}};
        if (!lattice.rootKnots[0].empty() || !lattice.rootKnots[1].empty() || !lattice.rootKnots[2].empty()) {
            json knots = json::array();
            for (int a = 0; a < 3; ++a) knots.push_back(lattice.rootKnots[static_cast<size_t>(a)]);  // [] = uniform
            out["root_knots"] = knots;
        }
        return true;
    };
    return format;
}

std::vector<VolumeFormat>& volumeFormats() {
    static std::vector<VolumeFormat> formats = [] {
        VolumeFormat net;
        net.kinds = {"net", "parallelepiped", "cylinder", "sphere", "prism", "loft"};
        net.read = [](const json& j, const std::string& path, std::shared_ptr<const core::Volume>& out) {
            core::LatticeNet parsed;
            if (Status s = parseLatticeNetJson(j, path, parsed); !s) return s;
            out = std::make_shared<const core::LatticeNet>(std::move(parsed));
            return Status::success();
        };
        net.write = [](const core::Volume& volume, json& out) {
            if (!volume.tensorNet()) return false;
            out = latticeNetJson(*volume.tensorNet());
            return true;
        };
        // A composite (Coquillart 1990, 3.1.2): {"kind": "composite", "parts": [lattice, lattice, ...]}, its
        // parts any of the net forms above, welded where their points meet.
        VolumeFormat composite;
        composite.kinds = {"composite"};
        composite.read = [](const json& j, const std::string& path, std::shared_ptr<const core::Volume>& out) {
            try {
                allowOnly(j, path, {"kind", "parts"});
                const json& parts = required(j, "parts", path);
                if (!parts.is_array() || parts.size() < 2) fail(path + ".parts", "expected an array of two or more lattices to weld");
                std::vector<std::shared_ptr<const core::LatticeNet>> blocks;
                for (size_t p = 0; p < parts.size(); ++p)
                    blocks.push_back(std::make_shared<const core::LatticeNet>(parseNet(parts[p], path + ".parts[" + std::to_string(p) + "]")));
                std::shared_ptr<const core::CompositeVolume> made;
                if (Status s = core::CompositeVolume::make(std::move(blocks), made); !s) fail(path + ".parts", s.message);
                out = std::move(made);
            } catch (const FieldError& e) {
                return Status::error(e.path + ": " + e.what);
            }
            return Status::success();
        };
        composite.write = [](const core::Volume& volume, json& out) {
            const core::CompositeVolume* made = volume.compositeVolume();
            if (!made) return false;
            json parts = json::array();
            for (const auto& block : made->blocks()) parts.push_back(latticeNetJson(*block));
            out = {{"kind", "composite"}, {"parts", parts}};
            return true;
        };
        return std::vector<VolumeFormat>{net, composite, tsplineVolumeFormat()};
    }();
    return formats;
}

}  // namespace

void registerVolumeFormat(VolumeFormat format) { volumeFormats().push_back(std::move(format)); }

Status parseVolumeJson(const json& j, const std::string& path, std::shared_ptr<const core::Volume>& out) {
    const std::string kind = j.is_object() && j.contains("kind") && j["kind"].is_string() ? j["kind"].get<std::string>() : std::string("net");
    for (const VolumeFormat& format : volumeFormats())
        if (std::find(format.kinds.begin(), format.kinds.end(), kind) != format.kinds.end()) return format.read(j, path, out);
    // Unknown kinds: the net parser names the known ones.
    return volumeFormats().front().read(j, path, out);
}

json volumeJson(const core::Volume& volume) {
    json out;
    for (const VolumeFormat& format : volumeFormats())
        if (format.write(volume, out)) return out;
    throw std::invalid_argument("no JSON format is registered for lattice kind " + volume.kindName());
}

}  // namespace sculpt::io
