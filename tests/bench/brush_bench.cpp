// The brush's benchmark cases (brush_bench.h).
#include "brush_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "bench_support.h"
#include "core/deform/brush.h"
#include "core/deform/vertex_normals.h"
#include "core/session/session.h"
#include "../core/cgal_meshes.h"
#include "../core/mesh_fixtures.h"

namespace sculpt::bench {

using namespace sculpt::core;

namespace {

// One random stroke as strokes_real draws them (stroke_past_stop too, with other ranges): stroke index i picks
// the falloff (i / 3 % 3), the direction (i % 3: along the vertex normal, a tangent, inward), symmetry in X for
// every fourth (i % 4 == 3) and the injectivity test (exact for odd i, else conic); the radius, the vertex and
// the pull's length come from rng, in that order (radius lo + span * u times the diagonal; pull likewise, in radii).
struct DrawnStroke {
    BrushSettings brush;
    InjectivitySettings injectivity;
    int vertex = -1;
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
    double pull = 0.0;  // world units
};

DrawnStroke drawStroke(std::mt19937& rng, int i, const Positions& normals, double diagonal, double radiusLo, double radiusSpan, double pullLo,
                       double pullSpan) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    DrawnStroke d;
    d.brush.radius = (radiusLo + radiusSpan * unit(rng)) * diagonal;
    d.brush.falloff = static_cast<BrushFalloff>(i / 3 % 3);
    if (i % 4 == 3) d.brush.symmetry.mirror[0] = true;
    d.injectivity = {i % 2 ? InjectivityMode::Exact : InjectivityMode::Conic, 6};
    d.vertex = std::uniform_int_distribution<int>(0, static_cast<int>(normals.rows()) - 1)(rng);
    const Eigen::Vector3d n = normals.row(d.vertex).transpose();
    d.direction = i % 3 == 0 ? n : i % 3 == 1 ? n.unitOrthogonal() : Eigen::Vector3d(-n);
    d.pull = (pullLo + pullSpan * unit(rng)) * d.brush.radius;
    return d;
}

// One of CGAL's meshes with its vertex normals and bounding diagonal; false (said on stderr, under the case's
// name) where it cannot be read.
struct BenchMesh {
    Positions positions, normals;
    Triangles triangles;
    double diagonal = 0.0;
};
bool loadBenchMesh(const std::string& name, const char* benchCase, BenchMesh& mesh) {
    std::string error;
    if (!test::loadCgalMesh(name, mesh.positions, mesh.triangles, error)) {
        std::fprintf(stderr, "%s: %s\n", benchCase, error.c_str());
        return false;
    }
    computeVertexNormals(mesh.positions, mesh.triangles, mesh.normals);
    mesh.diagonal = (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).norm();
    return true;
}

}  // namespace

void runBrushBenchmarks(const std::vector<std::string>& filters) {
    const auto wanted = [&](const char* name) { return wantedCase(filters, name); };
    if (wanted("strokes_real")) {
        for (const char* name : {"elephant.off", "camel.off", "armadillo.off"}) {
            if (getenv("SCULPT_BENCH_MESH") && std::string(getenv("SCULPT_BENCH_MESH")) + ".off" != name) continue;  // one mesh, to look at it
            Positions positions, normals;
            Triangles triangles;
            std::string error;
            if (!test::loadCgalMesh(name, positions, triangles, error)) {
                std::fprintf(stderr, "strokes_real: %s\n", error.c_str());
                continue;
            }
            for (int round = 0; getenv("SCULPT_BENCH_SUBDIVIDE") && round < atoi(getenv("SCULPT_BENCH_SUBDIVIDE")); ++round) {
                std::map<std::pair<int, int>, int> mid;
                std::vector<Eigen::Vector3d> extra;
                const auto at = [&](int a, int b) {
                    const auto key = std::minmax(a, b);
                    auto it = mid.find(key);
                    if (it != mid.end()) return it->second;
                    const int id = static_cast<int>(positions.rows() + extra.size());
                    extra.push_back(0.5 * (positions.row(a) + positions.row(b)).transpose());
                    mid.emplace(key, id);
                    return id;
                };
                Triangles finer(triangles.rows() * 4, 3);
                for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
                    const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
                    const int ab = at(a, b), bc = at(b, c), ca = at(c, a);
                    finer.row(4 * t) << a, ab, ca;
                    finer.row(4 * t + 1) << ab, b, bc;
                    finer.row(4 * t + 2) << ca, bc, c;
                    finer.row(4 * t + 3) << ab, bc, ca;
                }
                const Eigen::Index old = positions.rows();
                positions.conservativeResize(old + static_cast<Eigen::Index>(extra.size()), 3);
                for (size_t k = 0; k < extra.size(); ++k) positions.row(old + static_cast<Eigen::Index>(k)) = extra[k].transpose();
                triangles = finer;
            }
            computeVertexNormals(positions, triangles, normals);
            const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
            // Crossings at load (CGAL's camel has 20): the product lets such a contact shift within two rings of its
            // triangles (docs/formats.md, "Parts in contact"); a new pair there is counted apart, any other is a crossing.
            const std::vector<std::pair<int, int>> loadPairs = test::intersectingPairs(positions, triangles);
            const size_t initialPairs = loadPairs.size();
            std::vector<std::uint8_t> contactZone(static_cast<size_t>(triangles.rows()), 0);
            {
                std::vector<std::vector<int>> trianglesOf(static_cast<size_t>(positions.rows()));
                for (Eigen::Index t = 0; t < triangles.rows(); ++t)
                    for (int k = 0; k < 3; ++k) trianglesOf[static_cast<size_t>(triangles(t, k))].push_back(static_cast<int>(t));
                std::vector<int> frontier;
                for (const auto& [a, b] : loadPairs)
                    for (int t : {a, b})
                        if (!contactZone[static_cast<size_t>(t)]) contactZone[static_cast<size_t>(t)] = 1, frontier.push_back(t);
                for (int ring = 0; ring < 2; ++ring) {
                    std::vector<int> next;
                    for (int t : frontier)
                        for (int k = 0; k < 3; ++k)
                            for (int n : trianglesOf[static_cast<size_t>(triangles(t, k))])
                                if (!contactZone[static_cast<size_t>(n)]) contactZone[static_cast<size_t>(n)] = 1, next.push_back(n);
                    frontier = std::move(next);
                }
            }
            const std::set<std::pair<int, int>> atLoad(loadPairs.begin(), loadPairs.end());
            int shiftedContacts = 0;
            Session session;
            session.setMesh(positions, triangles);
            std::mt19937 rng(getenv("SCULPT_BENCH_SEED") ? atoi(getenv("SCULPT_BENCH_SEED")) : 2026);
            int full = 0, stopped = 0, refused = 0, crossings = 0, unrestored = 0, shapeCrosses = 0;
            // Symmetric strokes whose pull carries the grabbed point across the mirror plane (x through the box's
            // centre): its mirror image is pulled across the other way, and the two meet on the plane, which no
            // injective symmetric deformation does (they stop there, "by symmetry", unless the mesh's sides differ
            // enough that the images miss each other). Counted apart, with the share in full of the others.
            int acrossMirror = 0, fullNotAcross = 0;
            const double mirrorX = 0.5 * (positions.col(0).maxCoeff() + positions.col(0).minCoeff());
            std::map<std::string, int> stoppedBy;  // what stopped or refused a stroke: "triangles", "lattice", ...
            int fullByKind[3] = {0, 0, 0}, strokesByKind[3] = {0, 0, 0};
            std::vector<double> profiles, moveMs, reachedOfShapeLimit, addedVertices;
            for (int stroke = 0; stroke < 100; ++stroke) {
                const DrawnStroke drawn = drawStroke(rng, stroke, normals, diagonal, 0.03, 0.12, 0.1, 2.9);
                const BrushSettings& brush = drawn.brush;
                session.setInjectivity(drawn.injectivity);
                const int v = drawn.vertex;
                const int kind = stroke % 3;  // along the normal, a tangent, inward (independent of the falloff, stroke / 3 % 3)
                const Eigen::Vector3d& direction = drawn.direction;
                const double pull = drawn.pull;
                const Eigen::Vector3d source = positions.row(v).transpose();
                if (getenv("SCULPT_BENCH_STROKE") && atoi(getenv("SCULPT_BENCH_STROKE")) != stroke) continue;  // one stroke, to look at it
                OpReport report;
                session.dragVertex(v, source + pull * direction, report, brush);
                moveMs.push_back(report.wallMs);
                if (getenv("SCULPT_BENCH_VERBOSE") && report.wallMs > 1000.0)
                    std::fprintf(stderr, "  %s stroke %d vertex %d kind %d pull %.2f r radius %.3f diag falloff %d sym %d: %.0f ms, %s %.3f, %d vertices added\n", name, stroke, v,
                                 stroke % 3, pull / brush.radius, brush.radius / diagonal, stroke / 3 % 3, brush.symmetry.any() ? 1 : 0, report.wallMs,
                                 opStatusName(report.status), report.fractionApplied, report.verticesAdded);
                const bool across = brush.symmetry.any() && (source.x() - mirrorX) * (source.x() + pull * direction.x() - mirrorX) <= 0.0;
                acrossMirror += across;
                fullNotAcross += !across && report.status == OpStatus::Applied && report.fractionApplied == 1.0;
                ++strokesByKind[kind];
                if (report.status != OpStatus::Applied || report.fractionApplied < 1.0) {
                    ++stoppedBy[report.refusedBy.empty() ? std::string("other") : report.refusedBy];
                    // How hard was it? The falloff shape moves each vertex by the falloff of its rest distance
                    // from the grabbed point (and from its mirror image), as the profile below measures, and
                    // nothing else: where its triangles cross at the target (a part pushed into another), the
                    // pull cannot be carried without moving what lies ahead, which the brush's field does
                    // (brush_field.h) up to where the mesh's triangles, too coarse for the bend, would cross.
                    // Reported: how many stops are such strokes, and how far the brush got compared with where
                    // the falloff shape first crosses.
                    const Eigen::Vector3d centre = 0.5 * (positions.colwise().minCoeff() + positions.colwise().maxCoeff()).transpose();
                    const auto falloffShapeCrosses = [&](double share, bool oneSide = false) {
                        Positions shape = positions;
                        for (int mask = 0; mask <= (brush.symmetry.any() && !oneSide ? 1 : 0); ++mask) {
                            const Eigen::Vector3d grab = reflectPoint(source, mask, SymmetryFrame{centre});
                            const Eigen::Vector3d move = reflectPoint(source + share * pull * direction, mask, SymmetryFrame{centre}) - grab;
                            for (Eigen::Index r = 0; r < positions.rows(); ++r) {
                                const double rho = (positions.row(r).transpose() - grab).norm();
                                if (rho < brush.radius) shape.row(r) += brushProfile(brush.falloff, rho / brush.radius) * move.transpose();
                            }
                        }
                        for (const std::pair<int, int>& pair : test::intersectingPairs(shape, triangles))
                            if (!atLoad.count(pair) && !(contactZone[static_cast<size_t>(pair.first)] && contactZone[static_cast<size_t>(pair.second)]))
                                return true;
                        return false;
                    };
                    const bool crosses = falloffShapeCrosses(1.0);
                    shapeCrosses += crosses;
                    if (crosses) {
                        // Where the falloff shape first crosses (to 1/64 of the pull): the share the brush reached, of it.
                        double lo = 0.0, hi = 1.0;
                        for (int iteration = 0; iteration < 6; ++iteration) (falloffShapeCrosses(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
                        const double reached = report.status == OpStatus::Applied ? report.fractionApplied : 0.0;
                        if (hi > 0.0) reachedOfShapeLimit.push_back(reached / hi);
                    }
                    if (getenv("SCULPT_BENCH_VERBOSE"))
                        std::fprintf(stderr, "  %s stroke %d: the falloff shape at the target %s%s\n", name, stroke, crosses ? "crosses itself" : "is crossing-free",
                                     !brush.symmetry.any() || !crosses ? "" : falloffShapeCrosses(1.0, true) ? " (on one side alone too)" : " (not on one side alone)");
                }
                if (getenv("SCULPT_BENCH_VERBOSE") && (report.status != OpStatus::Applied || report.fractionApplied < 1.0))
                    std::fprintf(stderr, "  %s stroke %d vertex %d kind %d pull %.2f r radius %.3f diag falloff %d sym %d: %s %.3f by %s (%s)\n", name,
                                 stroke, v, kind, pull / brush.radius, brush.radius / diagonal, stroke / 3 % 3, brush.symmetry.any() ? 1 : 0,
                                 opStatusName(report.status), report.fractionApplied, report.refusedBy.c_str(), report.reason.c_str());
                if (report.status != OpStatus::Applied) {
                    ++refused;
                    unrestored += session.mesh().positions.rows() != positions.rows() || session.mesh().positions != positions;  // a refused stroke changes nothing
                    continue;
                }
                (report.fractionApplied == 1.0 ? full : stopped) += 1;
                fullByKind[kind] += report.fractionApplied == 1.0;
                // The independent exact triangle test (tests/core/mesh_fixtures.h), on the whole mesh (refined under the
                // pull where the stroke split triangles: a triangle appended by a split is in the load contacts' zone
                // when its corners are, a new vertex when both ends of its edge are).
                int newPairs = 0;
                const Triangles& now = session.mesh().triangles;
                std::vector<std::uint8_t> zoneVertex(static_cast<size_t>(session.mesh().positions.rows()), 0);
                for (Eigen::Index t = 0; t < triangles.rows(); ++t)
                    if (contactZone[static_cast<size_t>(t)])
                        for (int k = 0; k < 3; ++k) zoneVertex[static_cast<size_t>(triangles(t, k))] = 1;
                {
                    size_t next = static_cast<size_t>(positions.rows());
                    for (const EdgeSplit& split : session.refinement().appliedSplits())
                        zoneVertex[next++] = zoneVertex[static_cast<size_t>(split.a)] && zoneVertex[static_cast<size_t>(split.b)];
                }
                const auto inZone = [&](int t) {
                    if (t < triangles.rows()) return contactZone[static_cast<size_t>(t)] != 0;
                    return zoneVertex[static_cast<size_t>(now(t, 0))] && zoneVertex[static_cast<size_t>(now(t, 1))] && zoneVertex[static_cast<size_t>(now(t, 2))];
                };
                addedVertices.push_back(static_cast<double>(session.mesh().positions.rows() - positions.rows()));
                for (const std::pair<int, int>& pair : test::intersectingPairs(session.mesh().positions, now)) {
                    if (atLoad.count(pair)) continue;
                    if (inZone(pair.first) && inZone(pair.second)) ++shiftedContacts;
                    else ++newPairs;
                }
                crossings += newPairs;
                if (getenv("SCULPT_BENCH_VERBOSE") && newPairs != 0)
                    std::fprintf(stderr, "  %s stroke %d kind %d pull %.2f r radius %.3f diag falloff %d sym %d: %d new crossing pairs (%d at load)\n", name,
                                 stroke, kind, pull / brush.radius, brush.radius / diagonal, stroke / 3 % 3, brush.symmetry.any() ? 1 : 0,
                                 newPairs, static_cast<int>(initialPairs));
                if (kind == 0 && report.fractionApplied == 1.0 && !brush.symmetry.any()) {
                    double squares = 0.0;
                    int within = 0;
                    for (Eigen::Index r = 0; r < positions.rows(); ++r) {
                        const double rho = (positions.row(r) - positions.row(v)).norm();
                        if (rho >= brush.radius) continue;
                        const double share = (session.mesh().positions.row(r) - positions.row(r)).dot(direction.transpose()) / pull;
                        squares += std::pow(share - brushProfile(brush.falloff, rho / brush.radius), 2);
                        ++within;
                    }
                    if (within > 0) profiles.push_back(std::sqrt(squares / within));
                }
                session.undo(report);
                unrestored += session.mesh().positions.rows() != positions.rows() || session.mesh().triangles != triangles ||
                              (session.mesh().positions - positions).cwiseAbs().maxCoeff() > 1e-12 * diagonal;  // undo is exact
            }
            std::string by;
            for (const auto& [what, count] : stoppedBy) by += (by.empty() ? "" : ", ") + ("\"" + what + "\": " + std::to_string(count));
            char extra[1800];
            std::snprintf(extra, sizeof extra,
                          "\"mesh\": \"%s\", \"applied_in_full\": %d, \"stopped_short\": %d, \"refused\": %d, \"falloff_shape_crosses_at_target\": %d, \"applied_in_full_of_the_rest\": %.3f, \"across_mirror_plane\": %d, \"applied_in_full_not_across_mirror_plane\": \"%d/%d\", \"reached_of_falloff_shape_limit_median\": %.2f, \"profile_rms_median\": %.3f, \"profile_rms_max\": %.3f, "
                          "\"ms_p95_max\": [%.0f, %.0f], \"profiles\": %zu, \"profiles_within_0.08\": %d, \"vertices_added_median_max\": [%.0f, %.0f], \"crossing_pairs\": %d, \"shifted_load_contact_pairs\": %d, \"full_normal_tangent_inward\": [\"%d/%d\", \"%d/%d\", \"%d/%d\"], \"stopped_by\": {%s}, \"not_restored\": %d",
                          name, full, stopped, refused, shapeCrosses, full / std::max(1.0, 100.0 - shapeCrosses), acrossMirror, fullNotAcross, 100 - acrossMirror,
                          reachedOfShapeLimit.empty() ? NAN : median(reachedOfShapeLimit), profiles.empty() ? NAN : median(profiles),
                          profiles.empty() ? NAN : *std::max_element(profiles.begin(), profiles.end()), percentile(moveMs, 0.95),
                          percentile(moveMs, 1.0), profiles.size(),
                          static_cast<int>(std::count_if(profiles.begin(), profiles.end(), [](double p) { return p <= 0.08; })),
                          addedVertices.empty() ? 0.0 : median(addedVertices), addedVertices.empty() ? 0.0 : *std::max_element(addedVertices.begin(), addedVertices.end()), crossings, shiftedContacts,
                          fullByKind[0], strokesByKind[0], fullByKind[1], strokesByKind[1], fullByKind[2], strokesByKind[2], by.c_str(), unrestored);
            printCase("strokes_real", positions.rows(), median(moveMs), extra);
        }
    }
    if (wanted("brush_move_1m")) {
        Positions positions;
        Triangles triangles;
        sphereMesh(1000000, positions, triangles);
        Session session;
        session.setMesh(positions, triangles);
        const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
        BrushSettings brush;
        brush.radius = 0.05 * diagonal;
        const int v = static_cast<int>(positions.rows()) / 3;
        const Eigen::Vector3d source = positions.row(v).transpose();
        const Eigen::Vector3d normal = source.normalized();
        std::vector<double> injectivity, triangle;
        OpReport report;
        int step = 0;
        session.stroke().beginAt({source}, {}, brush);
        const double ms = medianMs(10, [&] {
            ++step;
            session.stroke().update({source + 0.1 * step * brush.radius * normal}, report);
            injectivity.push_back(report.injectivityMs);
            triangle.push_back(report.triangleCheckMs);
        });
        session.stroke().end();
        char extra[200];
        std::snprintf(extra, sizeof extra, "\"status\": \"%s\", \"vertices_moved\": %d, \"injectivity_ms\": %.2f, \"triangle_check_ms\": %.2f",
                      opStatusName(report.status), report.verticesMoved, median(injectivity), median(triangle));
        printCase("brush_move_1m", positions.rows(), ms, extra);
    }
    if (wanted("stroke_coarse")) {
        // As the window strokes a coarse mesh: the point grabbed inside one of the elephant's 10 largest
        // triangles (its centroid), pulled along the triangle's normal to 3 radii in 20 mouse moves, radius 5%
        // of the diagonal; the triangles under the pull are split where the flat mesh would leave the tip short
        // of the cursor (or the triangles would cross). Reported: ms per move (median, max), vertices added per
        // stroke (median), and the strokes applied in full.
        Positions positions;
        Triangles triangles;
        std::string error;
        if (!test::loadCgalMesh("elephant.off", positions, triangles, error)) {
            std::fprintf(stderr, "stroke_coarse: %s\n", error.c_str());
            return;
        }
        const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
        std::vector<std::pair<double, int>> bySize;
        for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
            const Eigen::Vector3d a = positions.row(triangles(t, 0)), b = positions.row(triangles(t, 1)), c = positions.row(triangles(t, 2));
            bySize.push_back({-(b - a).cross(c - a).norm(), static_cast<int>(t)});
        }
        std::sort(bySize.begin(), bySize.end());
        Session session;
        session.setMesh(positions, triangles);
        BrushSettings brush;
        brush.radius = 0.05 * diagonal;
        std::vector<double> moveMs, added;
        int full = 0;
        for (int k = 0; k < 10; ++k) {
            const int t = bySize[static_cast<size_t>(k)].second;
            const Eigen::Vector3d a = positions.row(triangles(t, 0)), b = positions.row(triangles(t, 1)), c = positions.row(triangles(t, 2));
            const Eigen::Vector3d source = (a + b + c) / 3.0, normal = (b - a).cross(c - a).normalized();
            if (!session.stroke().beginAt({source}, {}, brush)) continue;
            OpReport report;
            for (int move = 1; move <= 20; ++move) {
                const auto start = std::chrono::steady_clock::now();
                session.stroke().update({source + 3.0 * brush.radius * move / 20.0 * normal}, report);
                moveMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            }
            full += report.status == OpStatus::Applied && report.fractionApplied == 1.0;
            session.stroke().end();
            added.push_back(static_cast<double>(session.mesh().positions.rows() - positions.rows()));
            session.undo(report);
        }
        char extra[300];
        std::snprintf(extra, sizeof extra, "\"max_ms\": %.1f, \"vertices_added_median\": %.0f, \"applied_in_full\": %d, \"strokes\": 10",
                      moveMs.empty() ? 0.0 : *std::max_element(moveMs.begin(), moveMs.end()), added.empty() ? 0.0 : median(added), full);
        printCase("stroke_coarse", positions.rows(), moveMs.empty() ? 0.0 : median(moveMs), extra);
    }
    if (wanted("strokes_moves")) {
        // strokes_real's strokes as the window makes them: each of the 100 drawn on CGAL's armadillo (or
        // SCULPT_BENCH_MESH) dragged in 10 mouse moves along its line to its pull. Reported: ms per move (median,
        // 95th and 99th percentile, the slowest) and the strokes whose last move applied in full.
        const std::string name = getenv("SCULPT_BENCH_MESH") ? std::string(getenv("SCULPT_BENCH_MESH")) + ".off" : "armadillo.off";
        BenchMesh mesh;
        if (!loadBenchMesh(name, "strokes_moves", mesh)) return;
        const Positions& positions = mesh.positions;
        std::mt19937 rng(getenv("SCULPT_BENCH_SEED") ? static_cast<unsigned>(atoi(getenv("SCULPT_BENCH_SEED"))) : 2026u);
        std::vector<double> moveMs;
        int inFull = 0;
        for (int stroke = 0; stroke < 100; ++stroke) {
            const DrawnStroke drawn = drawStroke(rng, stroke, mesh.normals, mesh.diagonal, 0.03, 0.12, 0.1, 2.9);
            Session session;
            session.setMesh(positions, mesh.triangles);
            session.setInjectivity(drawn.injectivity);
            const Eigen::Vector3d source = positions.row(drawn.vertex).transpose();
            if (!session.stroke().beginAt({source}, {}, drawn.brush)) continue;
            OpReport report;
            for (int move = 1; move <= 10; ++move) {
                const auto start = std::chrono::steady_clock::now();
                session.stroke().update({source + drawn.pull * move / 10.0 * drawn.direction}, report);
                moveMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            }
            inFull += report.status == OpStatus::Applied && report.fractionApplied == 1.0;
        }
        char extra[200];
        std::snprintf(extra, sizeof extra, "\"mesh\": \"%s\", \"moves\": %zu, \"ms_p95_p99_max\": [%.0f, %.0f, %.0f], \"applied_in_full\": %d", name.c_str(),
                      moveMs.size(), percentile(moveMs, 0.95), percentile(moveMs, 0.99), percentile(moveMs, 1.0), inFull);
        printCase("strokes_moves", positions.rows(), moveMs.empty() ? 0.0 : median(moveMs), extra);
    }
    if (wanted("stroke_past_stop")) {
        // As the window strokes a pull that cannot be carried all the way: random long pulls on CGAL's camel
        // (radius 6-14% of the diagonal, 2-3 radii along the normal, a tangent or inward; every fourth
        // symmetric, every other under the exact test), each dragged in 12 mouse moves along its line to twice
        // its length, until 6 strokes have stopped short. Every move past the first that stopped searches again
        // from where the last left it. Reported: ms of the move that first stopped (median), of the moves past
        // it (median, max), and their count.
        BenchMesh mesh;
        if (!loadBenchMesh("camel.off", "stroke_past_stop", mesh)) return;
        const Positions& positions = mesh.positions;
        const Triangles& triangles = mesh.triangles;
        const Positions& normals = mesh.normals;
        const double diagonal = mesh.diagonal;
        std::mt19937 rng(2026);
        std::vector<double> firstStopMs, pastStopMs;
        int stoppedStrokes = 0;
        for (int stroke = 0; stroke < 60 && stoppedStrokes < 6; ++stroke) {
            Session session;
            session.setMesh(positions, triangles);
            const DrawnStroke drawn = drawStroke(rng, stroke, normals, diagonal, 0.06, 0.08, 2.0, 1.0);
            session.setInjectivity(drawn.injectivity);
            const Eigen::Vector3d source = positions.row(drawn.vertex).transpose(), direction = drawn.direction;
            const double pull = drawn.pull;
            if (!session.stroke().beginAt({source}, {}, drawn.brush)) continue;
            bool stopped = false;
            for (int move = 1; move <= 12; ++move) {
                OpReport report;
                const auto start = std::chrono::steady_clock::now();
                session.stroke().update({source + 2.0 * pull * move / 12.0 * direction}, report);
                const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
                if (stopped) pastStopMs.push_back(ms);
                else if (report.fractionApplied < 1.0 || report.status != OpStatus::Applied) firstStopMs.push_back(ms), stopped = true;
            }
            stoppedStrokes += stopped;
        }
        char extra[300];
        std::snprintf(extra, sizeof extra, "\"strokes_stopped\": %d, \"first_stop_ms_median\": %.0f, \"past_stop_ms_max\": %.0f, \"moves_past_stop\": %zu",
                      stoppedStrokes, firstStopMs.empty() ? 0.0 : median(firstStopMs),
                      pastStopMs.empty() ? 0.0 : *std::max_element(pastStopMs.begin(), pastStopMs.end()), pastStopMs.size());
        printCase("stroke_past_stop", positions.rows(), pastStopMs.empty() ? 0.0 : median(pastStopMs), extra);
    }
}

}  // namespace sculpt::bench
