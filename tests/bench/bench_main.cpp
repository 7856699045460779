// sculpt_bench: speed of the engine's hot paths (docs/benchmarks.md). One JSON line per case, median of
// >= 10 runs. Not a test: nothing here asserts a time.
//
// Usage: sculpt_bench [case-name-substring ...]   (no argument: every case)
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <omp.h>

#include "bench_support.h"
#include "brush_bench.h"
#include "eval_limit.h"
#include "effd_bench.h"
#include "io_bench.h"
#include "tspline_bench.h"
#include "injectivity_bench.h"
#include "core/spline/bernstein_box.h"
#include "core/injectivity/injectivity.h"
#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"
#include "core/injectivity/self_intersection.h"
#include "core/session/session.h"
#include "core/deform/vertex_normals.h"
#include "../core/cgal_meshes.h"
#include "../core/mesh_fixtures.h"
#include "subdivided_scan.h"
#ifdef SCULPT_BENCH_RENDER
#include "render_bench.h"
#endif
#ifdef SCULPT_BENCH_WINDOW
#include "window_bench.h"
#endif

using namespace sculpt;
using namespace sculpt::core;
using sculpt::bench::bumpySphere;
using sculpt::bench::sphereMesh;

namespace {

std::vector<std::string> gFilters;

bool wanted(const std::string& name) {
    if (gFilters.empty()) return true;
    for (const std::string& f : gFilters)
        if (name.find(f) != std::string::npos) return true;
    return false;
}

Lattice cubicLattice(int resolution, const Positions& points) {
    LatticeSettings s;
    s.resolution = {resolution, resolution, resolution};
    Lattice lattice;
    makeLattice(s, points, lattice);
    return lattice;
}

void benchEvaluation(const Positions& points) {
    const int n = static_cast<int>(points.rows());
    for (int resolution : {8, 16}) {
        const std::string name = "eval_full_" + std::to_string(resolution);
        if (!wanted(name)) continue;
        Lattice lattice = cubicLattice(resolution, points);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> d(-0.05, 0.05);
        for (int c = 0; c < lattice.controlPointCount(); ++c) lattice.displacement.row(c) << d(rng), d(rng), d(rng);
        const Embedding embedding = embedVertices(lattice, points);
        Positions positions = points;
        const double ms = bench::medianMs(15, [&] { evaluateAll(lattice, embedding, positions); });
        bench::printCase(name, n, ms, std::string("\"kernel\": \"") + evaluationKernelName() + "\", \"precision\": \"double\"");
        // The same kernel writing the vertices in cell order (no scatter to the mesh's order), side by side in
        // this run: what storing the mesh in cell order would save. (Not issue 12's "limit", a leaner kernel.)
        if (!wanted(name + "_in_cell_order")) continue;
        std::vector<double> inCellOrder(3 * static_cast<size_t>(embedding.insideCount()));
        const double cellOrderMs = bench::medianMs(15, [&] { evaluateAllInCellOrder(lattice, embedding, inCellOrder.data()); });
        const double productMs = bench::medianMs(15, [&] { evaluateAll(lattice, embedding, positions); });
        char extra[160];
        std::snprintf(extra, sizeof extra, "\"in_cell_order_ms\": %.4f, \"ratio\": %.2f, \"kernel\": \"%s\"", cellOrderMs,
                      productMs / cellOrderMs, evaluationKernelName());
        bench::printCase(name + "_in_cell_order", n, productMs, extra);
        if (!wanted(name + "_vs_limit") || !bench::limitKernelApplies(lattice)) continue;
        // Issue 12, point 4: evaluateAll against the reference of eval_limit.h (the same power form, AVX2
        // intrinsics, cell order in and out, nothing else), run alternately so both see the same machine state.
        const size_t inside = static_cast<size_t>(embedding.insideCount());
        std::vector<double> limitX(inside), limitY(inside), limitZ(inside);
        std::vector<double> engineTimes, limitTimes;
        for (int run = 0; run <= 21; ++run) {
            auto start = std::chrono::steady_clock::now();
            evaluateAll(lattice, embedding, positions);
            const double engine = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            start = std::chrono::steady_clock::now();
            bench::evaluateCubicLimit(lattice, embedding, limitX.data(), limitY.data(), limitZ.data());
            const double limit = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            if (run == 0) continue;  // warm-up
            engineTimes.push_back(engine);
            limitTimes.push_back(limit);
        }
        double difference = 0.0;  // the two must compute the same positions
        for (size_t entry = 0; entry < inside; ++entry) {
            const int v = embedding.order[entry];
            difference = std::max({difference, std::abs(positions(v, 0) - limitX[entry]), std::abs(positions(v, 1) - limitY[entry]),
                                   std::abs(positions(v, 2) - limitZ[entry])});
        }
        const double engineMs = bench::median(engineTimes), limitMs = bench::median(limitTimes);
        std::snprintf(extra, sizeof extra, "\"limit_ms\": %.4f, \"ratio\": %.2f, \"max_abs_difference\": %.1e, \"kernel\": \"%s\"",
                      limitMs, engineMs / limitMs, difference, evaluationKernelName());
        bench::printCase(name + "_vs_limit", n, engineMs, extra);
    }
}

void benchSparseUpdate(const Positions& points) {
    const int n = static_cast<int>(points.rows());
    LatticeSettings s;
    s.resolution = {16, 16, 16};
    if (wanted("update_sparse_16")) {
        // The engine's sparse update after a single-point drag (Hu et al. eq. 7 moves the 64 control points of
        // the source's support): only the vertices of the cells those reach, only the changed terms.
        Lattice lattice;
        makeLattice(s, points, lattice);
        const Embedding embedding = embedVertices(lattice, points);
        Positions positions = points;
        Eigen::Vector3d params;
        restParameters(lattice, points.row(n / 3).transpose(), params);
        Eigen::MatrixX3d displacement(1, 3);
        displacement << 0.001, 0.0005, 0.0;
        const DirectManipulationResult solved = directManipulation(lattice, {params}, displacement);
        IncrementScratch scratch;
        std::vector<int> moved;
        const double ms = bench::medianMs(15, [&] {
            applyControlDelta(lattice, solved.delta);
            evaluateIncrement(lattice, embedding, solved.delta.indices, solved.delta.deltas, 1.0, positions, scratch, nullptr);
        });
        evaluateIncrement(lattice, embedding, solved.delta.indices, solved.delta.deltas, 0.0, positions, scratch, &moved);
        char extra[160];
        std::snprintf(extra, sizeof extra, "\"vertices_in_reach\": %zu, \"fraction\": %.4f", moved.size(),
                      static_cast<double>(moved.size()) / n);
        bench::printCase("update_sparse_16", n, ms, extra);
    }
    if (wanted("drag_step_16")) {
        // One mouse move of an interactive drag: solve, conic injectivity test of the changed cells, sparse update.
        Session session;
        Triangles none(0, 3);
        session.setMesh(points, none, s);
        Eigen::Vector3d params;
        session.parametersOfVertex(n / 3, params);
        const Eigen::Vector3d start = session.mesh().positions.row(n / 3).transpose();
        int step = 0;
        session.stroke().begin({params});
        OpReport report;
        const double ms = bench::medianMs(15, [&] {
            ++step;
            session.stroke().update({start + Eigen::Vector3d(0.001 * step, 0.0005 * step, 0.0)}, report);
        });
        session.stroke().end();
        char extra[160];
        std::snprintf(extra, sizeof extra, "\"vertices_moved\": %d, \"injectivity_ms\": %.3f", report.verticesMoved,
                      report.injectivityMs);
        bench::printCase("drag_step_16", n, ms, extra);
    }
}

void benchSolves() {
    Positions box(2, 3);
    box << 0, 0, 0, 1, 1, 1;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    if (wanted("solve_single")) {
        const Lattice lattice = cubicLattice(16, box);
        const Eigen::Vector3d t(unit(rng), unit(rng), unit(rng));
        Eigen::MatrixX3d d(1, 3);
        d << 0.1, 0.0, -0.05;
        const int inner = 1000;
        const double ms = bench::medianMs(11, [&] {
            for (int i = 0; i < inner; ++i) {
                const DirectManipulationResult r = directManipulation(lattice, {t}, d);
                if (r.delta.indices.empty()) std::abort();
            }
        });
        bench::printCase("solve_single", 1, ms / inner, "\"median_us\": " + std::to_string(1000.0 * ms / inner));
    }
    if (wanted("solve_multi_32")) {
        const Lattice lattice = cubicLattice(16, box);
        std::vector<Eigen::Vector3d> params;
        Eigen::MatrixX3d d(32, 3);
        for (int f = 0; f < 32; ++f) {
            params.emplace_back(unit(rng), unit(rng), unit(rng));
            d.row(f) << unit(rng) * 0.1, unit(rng) * 0.1, unit(rng) * 0.1;
        }
        const double ms = bench::medianMs(21, [&] {
            const DirectManipulationResult r = directManipulation(lattice, params, d);
            if (r.delta.indices.empty()) std::abort();
        });
        bench::printCase("solve_multi_32", 32, ms);
    }
}

void benchParameters(const Positions& points) {
    if (!wanted("params_1m")) return;
    const Lattice lattice = cubicLattice(16, points);
    const int n = static_cast<int>(points.rows());
    std::vector<double> out(3 * static_cast<size_t>(n));
    const double ms = bench::medianMs(15, [&] {
#pragma omp parallel for schedule(static)
        for (int v = 0; v < n; ++v) {
            Eigen::Vector3d t;
            restParameters(lattice, points.row(v).transpose(), t);
            out[3 * static_cast<size_t>(v)] = t.x();
            out[3 * static_cast<size_t>(v) + 1] = t.y();
            out[3 * static_cast<size_t>(v) + 2] = t.z();
        }
    });
    bench::printCase("params_1m", n, ms);
    if (wanted("embed_1m")) {
        const double embedMs = bench::medianMs(10, [&] { Embedding e = embedVertices(lattice, points); });
        bench::printCase("embed_1m", n, embedMs);
    }
}

// PyGeM's FFD (pygem.FFD, test_ffd_sphere_mod's 3x2x2 box, rotated) of 1M points by the native Bernstein box
// (core/spline/bernstein_box.h), what the Python module's sculpt.FFD runs; PyGeM takes 3.9 s for 1M points here.
void benchBernsteinBox(const Positions& points) {
    if (!wanted("box_ffd_1m")) return;
    BernsteinBox box;
    box.controlPoints = {3, 2, 2};
    box.origin = Eigen::Vector3d(-1.2, -1.2, -1.2);
    box.lengths = Eigen::Vector3d(2.4, 2.4, 2.4);
    box.rotationDegrees = Eigen::Vector3d(0.0, 10.0, 15.0);
    for (std::vector<double>& mu : box.mu) mu.assign(12, 0.0);
    box.mu[0][2] = 0.8;
    box.mu[1][2] = -0.5;
    box.mu[2][2] = -1.0;
    Positions out;
    const double ms = bench::medianMs(9, [&] { deformByBernsteinBox(box, points, out); });
    bench::printCase("box_ffd_1m", points.rows(), ms);
}

// Issue 3's cases: a drag that must be subdivided on a 100k-vertex mesh, undoing a 16-step composed
// operation on 1M vertices, and the history's size after 100 operations on 1M vertices.
void benchSubdivision() {
    const LatticeSettings settings = [] {
        LatticeSettings s;
        s.resolution = {8, 8, 8};
        return s;
    }();
    Triangles none(0, 3);
    if (wanted("subdivided_drag_100k")) {
        const Positions points = bumpySphere(100000);
        Session session;
        session.setMesh(points, none, settings);
        const int v = 100000 / 3;
        const Eigen::Vector3d source = points.row(v).transpose();
        // Over-extension: far beyond the support, so the conic test fails and InjectSubdiv splits it.
        const Eigen::Vector3d target = source + Eigen::Vector3d(0.9, 0.5, -0.6);
        OpReport report;
        const double ms = bench::medianMs(10, [&] { session.drag({{source, target}}, report); },
                                          [&] { if (session.history().cursor() > 0) session.undo(report); });
        session.undo(report);
        session.drag({{source, target}}, report);
        char extra[200];
        std::snprintf(extra, sizeof extra, "\"sub_steps\": %d, \"depth\": %d, \"status\": \"%s\", \"injectivity_ms\": %.3f",
                      report.subSteps, report.depthReached, opStatusName(report.status), report.injectivityMs);
        bench::printCase("subdivided_drag_100k", 100000, ms, extra);
    }
    if (wanted("undo_composed_1m")) {
        const Positions points = bumpySphere(1000000);
        Session session;
        session.setMesh(points, none, settings);
        session.setInjectivity({InjectivityMode::Conic, 4});  // at most 16 steps
        const int v = 1000000 / 3;
        const Eigen::Vector3d source = points.row(v).transpose();
        const Eigen::Vector3d target = source + Eigen::Vector3d(0.9, 0.5, -0.6);
        OpReport report;
        session.drag({{source, target}}, report);
        const int steps = report.subSteps;
        const double ms = bench::medianMs(10, [&] { session.undo(report); }, [&] {
            if (session.history().cursor() == 0) session.redo(report);
        });
        char extra[120];
        std::snprintf(extra, sizeof extra, "\"sub_steps\": %d", steps);
        bench::printCase("undo_composed_1m", 1000000, ms, extra);
    }
    if (wanted("history_bytes_1m_100ops")) {
        const Positions points = bumpySphere(1000000);
        Session session;
        session.setMesh(points, none, settings);
        std::mt19937 rng(5);
        std::uniform_int_distribution<int> vertex(0, 999999);
        std::uniform_real_distribution<double> d(-1.0, 1.0);
        int subdivided = 0;
        const auto start = std::chrono::steady_clock::now();
        for (int op = 0; op < 100; ++op) {
            const int v = vertex(rng);
            const double size = op % 5 == 4 ? 0.6 : 0.05;  // every fifth operation needs subdividing
            OpReport report;
            session.dragVertex(v, session.mesh().positions.row(v).transpose() + size * Eigen::Vector3d(d(rng), d(rng), d(rng)), report);
            subdivided += report.subSteps > 1;
        }
        const double totalMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        std::printf("{\"case\": \"history_bytes_1m_100ops\", \"n\": 1000000, \"bytes\": %zu, \"operations\": %d, "
                    "\"subdivided\": %d, \"frames\": %d, \"total_ms\": %.1f}\n",
                    session.historyBytes(), session.history().cursor(), subdivided, session.cage().frameDepth(), totalMs);
    }
}

// A geodesic sphere: the icosahedron's faces cut into frequency^2 triangles each and projected onto the unit sphere,
// 10 f^2 + 2 vertices of near-equilateral triangles (what a remeshed scan has, unlike the latitude-longitude sphere,
// whose equal rings make slivers 1/sin(latitude) to 1 near the poles). A grid point is named by its integer weights on
// the icosahedron's corners, sorted by corner, so the points shared by two faces are one vertex, computed once.
void geodesicSphereMesh(int frequency, Positions& positions, Triangles& triangles) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    const double corner[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                  {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    std::map<std::array<int, 6>, int> ids;
    std::vector<Eigen::Vector3d> points;
    const auto vertex = [&](const int (&face)[3], int i, int j) {
        std::array<std::pair<int, int>, 3> weights = {{{face[0], frequency - i - j}, {face[1], i}, {face[2], j}}};
        std::sort(weights.begin(), weights.end());
        std::array<int, 6> key{};
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        int n = 0;
        for (const auto& [c, w] : weights)
            if (w > 0) {
                key[2 * n] = c, key[2 * n + 1] = w, ++n;
                p += w * Eigen::Vector3d(corner[c][0], corner[c][1], corner[c][2]);
            }
        const auto [it, added] = ids.emplace(key, static_cast<int>(points.size()));
        if (added) points.push_back(p.normalized());
        return it->second;
    };
    std::vector<Eigen::Vector3i> tris;
    for (const auto& face : faces)
        for (int i = 0; i < frequency; ++i)
            for (int j = 0; i + j < frequency; ++j) {
                const int a = vertex(face, i, j), b = vertex(face, i + 1, j), c = vertex(face, i, j + 1);
                tris.emplace_back(a, b, c);
                if (i + j + 1 < frequency) tris.emplace_back(b, vertex(face, i + 1, j + 1), c);
            }
    positions.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t v = 0; v < points.size(); ++v) positions.row(static_cast<Eigen::Index>(v)) = points[v].transpose();
    triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (size_t t = 0; t < tris.size(); ++t) triangles.row(static_cast<Eigen::Index>(t)) = tris[t].transpose();
}

// One drag of one vertex on a whole mesh in a cubic lattice of this resolution (lattice test conic), by `size` times
// the mesh's box diagonal, undone between runs: its median ms and the triangle check's.
void benchTriangleCheckDrag(const char* name, const Positions& positions, const Triangles& triangles, int resolution,
                            double size) {
    LatticeSettings settings;
    settings.resolution = {resolution, resolution, resolution};
    Session session;
    const auto start = std::chrono::steady_clock::now();
    session.setMesh(positions, triangles, settings);
    const double setMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    session.setInjectivity({InjectivityMode::Conic, 6});
    const int n = static_cast<int>(positions.rows());
    const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
    const int v = n / 3;
    const Eigen::Vector3d source = positions.row(v).transpose();
    const Eigen::Vector3d target = source + size * diagonal * Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
    OpReport report;
    std::vector<double> checkMs;
    const double ms = bench::medianMs(10, [&] {
        session.drag({{source, target}}, report);
        checkMs.push_back(report.triangleCheckMs);
    }, [&] { if (session.history().cursor() > 0) session.undo(report); });
    char extra[320];
    std::snprintf(extra, sizeof extra,
                  "\"triangle_check_ms\": %.2f, \"triangles\": %lld, \"vertices_moved\": %d, \"status\": \"%s\", \"sub_steps\": %d, "
                  "\"set_mesh_ms\": %.0f",
                  bench::median(checkMs), static_cast<long long>(triangles.rows()), report.verticesMoved,
                  opStatusName(report.status), report.subSteps, setMs);
    bench::printCase(name, n, ms, extra);
}

// The triangle check of issue 9 on 1M vertices (2M triangles): building its index with the load-time count of
// crossing pairs, and one drag that moves a few percent of the mesh (32^3 lattice), about a sixth (16^3), or
// nearly all of it (8^3), on the latitude-longitude sphere. The whole-mesh drag also on meshes whose triangles are
// a scan's: a geodesic sphere of 1M vertices, and CGAL's armadillo after three Loop subdivisions (1.66M vertices).
// The drags are 4.3% of the diagonal (0.15 on the unit sphere).
void benchTriangleCheck() {
    if (!wanted("triangle_check_all_pairs_1m") && !wanted("triangle_check_local_1m") && !wanted("triangle_check_mid_1m") &&
        !wanted("triangle_check_global_1m") && !wanted("triangle_check_global_1m_geodesic") &&
        !wanted("triangle_check_global_armadillo_loop3"))
        return;
    const double size = 0.15 / (2.0 * std::sqrt(3.0));
    Positions positions;
    Triangles triangles;
    if (wanted("triangle_check_all_pairs_1m") || wanted("triangle_check_local_1m") || wanted("triangle_check_mid_1m") ||
        wanted("triangle_check_global_1m")) {
        sphereMesh(1000000, positions, triangles);
        const int n = static_cast<int>(positions.rows());
        if (wanted("triangle_check_all_pairs_1m")) {
            const double ms = bench::medianMs(3, [&] { findSelfIntersections(positions, triangles); });
            bench::printCase("triangle_check_all_pairs_1m", n, ms, "\"triangles\": " + std::to_string(triangles.rows()));
        }
        for (const auto& [name, resolution, share] : {std::tuple<const char*, int, double>{"triangle_check_local_1m", 32, 1.0 / 15},
                                                      std::tuple<const char*, int, double>{"triangle_check_mid_1m", 16, 2.0 / 15},
                                                      std::tuple<const char*, int, double>{"triangle_check_global_1m", 8, 1.0}})
            if (wanted(name)) benchTriangleCheckDrag(name, positions, triangles, resolution, share * size);
    }
    if (wanted("triangle_check_global_1m_geodesic")) {
        geodesicSphereMesh(316, positions, triangles);
        benchTriangleCheckDrag("triangle_check_global_1m_geodesic", positions, triangles, 8, size);
    }
    if (wanted("triangle_check_global_armadillo_loop3")) {
        std::string error;
        if (!bench::loopSubdividedCgalMesh("armadillo.off", 3, positions, triangles, error))
            bench::printError(std::cout, "triangle_check_global_armadillo_loop3", error);
        else
            benchTriangleCheckDrag("triangle_check_global_armadillo_loop3", positions, triangles, 8, size);
    }
}

// The brush on real meshes (issue "Sculpting as a sculptor expects", point 5): 100 random strokes on each of
// three of CGAL's meshes, and one brush move on a 1M-vertex sphere.
// Certification on real scans (issue "Certification that decides", point 6), each with the share of its time in
// each test: a T-spline drag step on CGAL's armadillo (26k vertices, depth 4, weights 100:1), a whole-cage drag of
// one vertex (8^3 cubic lattice: every vertex moves, so every triangle is checked), and every control point of a
// 5^3 lattice turned 90 degrees about z in one move under the conic test.
void benchCertification() {
    if (!wanted("certify_tspline_real") && !wanted("triangle_check_global_26k") && !wanted("rotate_lattice_conic")) return;
    Positions positions;
    Triangles triangles;
    std::string error;
    if (!test::loadCgalMesh("armadillo.off", positions, triangles, error)) {
        bench::printError(std::cout, "certify_tspline_real", error);
        return;
    }
    const int n = static_cast<int>(positions.rows());
    const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
    // The reports' medians: how many applied in full, the lattice test's and the triangle check's ms and shares.
    const auto print = [&](const std::string& name, const std::vector<OpReport>& reports, double ms, const std::string& more) {
        std::vector<double> l, t, w;
        int applied = 0;
        for (const OpReport& r : reports) {
            applied += r.status == OpStatus::Applied && r.fractionApplied == 1.0;
            l.push_back(r.injectivityMs - r.triangleCheckMs);
            t.push_back(r.triangleCheckMs);
            w.push_back(r.wallMs);
        }
        const double lattice = bench::median(l), tri = bench::median(t), wall = bench::median(w);
        char extra[400];
        std::snprintf(extra, sizeof extra,
                      "\"applied_in_full\": \"%d of %zu\", \"lattice_test_ms\": %.2f, \"triangle_check_ms\": %.2f, \"lattice_share\": %.2f, "
                      "\"triangle_share\": %.2f%s",
                      applied, reports.size(), lattice, tri, wall > 0 ? lattice / wall : 0.0, wall > 0 ? tri / wall : 0.0, more.c_str());
        bench::printCase(name, n, ms, extra);
    };
    // `step` timed `runs` times after a warm-up, the history taken back to `keep` entries before each; the timed
    // runs' reports in `reports`.
    const auto timed = [](Session& session, int keep, int runs, const std::function<OpReport()>& step, std::vector<OpReport>& reports) {
        reports.clear();
        const double ms = bench::medianMs(
            runs, [&] { reports.push_back(step()); },
            [&] {
                OpReport undone;
                while (session.history().cursor() > keep) session.undo(undone);
            });
        reports.erase(reports.begin());  // the warm-up
        return ms;
    };
    // Drags of `length` (a fraction of the diagonal) at vertices spread over the mesh, one after another.
    const auto spreadDrags = [&](Session& session, double length) {
        return [&session, length, diagonal, n, next = 0]() mutable {
            const int v = (next++ * 2909 + 17) % n;
            const Eigen::Vector3d from = session.mesh().positions.row(v).transpose();
            OpReport report;
            session.dragVertex(v, from + length * diagonal * Eigen::Vector3d(0.3, -0.5, 0.8).normalized(), report);
            return report;
        };
    };
    if (wanted("certify_tspline_real")) {
        for (const InjectivityMode mode : {InjectivityMode::Exact, InjectivityMode::Conic}) {
            Session session;
            LatticeSettings start;
            start.resolution = {4, 4, 4};
            session.setMesh(positions, triangles, start);
            session.setInjectivity({mode, 6});
            TSplineSetup setup;
            setup.octree.octree.depth = 4;
            OpReport report;
            if (Status s = session.tspline().setup(setup, report); !s) {
                bench::printError(std::cout, "certify_tspline_real", s.message);
                return;
            }
            // One drag step of 3% of the diagonal at each of 9 vertices spread over the mesh, each undone after.
            std::vector<OpReport> reports;
            const double ms = timed(session, 2, 9, spreadDrags(session, 0.03), reports);
            print(std::string("certify_tspline_real") + (mode == InjectivityMode::Conic ? "_conic" : ""), reports, ms,
                  ", \"depth\": 4, \"weight_ratio\": 100, \"drag\": \"3% of the diagonal\"");
        }
    }
    if (wanted("triangle_check_global_26k")) {
        LatticeSettings settings;
        settings.resolution = {8, 8, 8};
        Session session;
        session.setMesh(positions, triangles, settings);
        session.setInjectivity({InjectivityMode::Conic, 6});
        std::vector<OpReport> reports;
        const double ms = timed(session, 0, 9, spreadDrags(session, 0.05), reports);
        print("triangle_check_global_26k", reports, ms, ", \"vertices_moved\": " + std::to_string(reports.back().verticesMoved));
    }
    if (wanted("rotate_lattice_conic")) {
        LatticeSettings settings;
        settings.resolution = {5, 5, 5};
        Session session;
        session.setMesh(positions, triangles, settings);
        session.setInjectivity({InjectivityMode::Conic, 6});
        const Lattice& lattice = session.lattice();
        std::vector<int> ids;
        Eigen::MatrixX3d to(lattice.controlPointCount(), 3);
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (int c = 0; c < lattice.controlPointCount(); ++c) centre += lattice.controlPoint(c);
        centre /= lattice.controlPointCount();
        const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        for (int c = 0; c < lattice.controlPointCount(); ++c) {
            ids.push_back(c);
            to.row(c) = (centre + turn * (lattice.controlPoint(c) - centre)).transpose();
        }
        std::vector<OpReport> reports;
        const double ms = timed(session, 0, 5, [&] {
            OpReport report;
            session.moveControlPoints(ids, to, false, report);
            return report;
        }, reports);
        char more[96];
        std::snprintf(more, sizeof more, ", \"fraction_applied\": %.3f", reports.back().fractionApplied);
        print("rotate_lattice_conic", reports, ms, more);
    }
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) gFilters.emplace_back(argv[i]);
    std::fprintf(stderr, "sculpt_bench: %d OpenMP threads, evaluation kernel %s\n", omp_get_max_threads(),
                 evaluationKernelName());
    const Positions points = bumpySphere(1000000);
    benchEvaluation(points);
    benchSparseUpdate(points);
    benchSolves();
    benchParameters(points);
    benchBernsteinBox(points);
    sculpt::bench::runInjectivityBenchmarks(gFilters);
    sculpt::bench::runEffdBenchmarks(gFilters);
    sculpt::bench::runTSplineBenchmarks(gFilters);
    sculpt::bench::runIoBenchmarks(gFilters);
    benchSubdivision();
    benchTriangleCheck();
    benchCertification();
    sculpt::bench::runBrushBenchmarks(gFilters);
#ifdef SCULPT_BENCH_RENDER
    // The group runs for its name or any of its cases' names ("render_100k" starts with "render").
    const auto wantedGroup = [](const std::string& prefix) {
        if (wanted(prefix)) return true;
        for (const std::string& f : gFilters)
            if (f.rfind(prefix, 0) == 0) return true;
        return false;
    };
    if (wantedGroup("render") || wantedGroup("upload") || wantedGroup("full_update")) sculpt::render::runRenderBenchmarks(std::cout);
    if (wanted("gpu_drag_1m") || wanted("gpu_drag_10m"))
        sculpt::render::runGpuDragBenchmarks(std::cout, wanted("gpu_drag_10m"));
#endif
#ifdef SCULPT_BENCH_WINDOW
    sculpt::bench::runWindowBenchmarks(std::cout, gFilters);  // runs only the cases gFilters asks for
#endif
    return 0;
}
