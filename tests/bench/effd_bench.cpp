// EFFD benchmarks: freezing, evaluation and a drag step on a cylindrical lattice (effd_bench.h).
#include "effd_bench.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <random>

#include "bench_support.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"
#include "core/session/session.h"

namespace sculpt::bench {

using namespace sculpt::core;

namespace {

bool wanted(const std::vector<std::string>& filters, const std::string& name) { return wantedCase(filters, name); }

// n points uniformly in the cylinder of radius 1 and height 2 around the z axis (fixed seed).
Positions pointsInCylinder(int n) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Positions p(n, 3);
    for (int v = 0; v < n; ++v) {
        const double r = 0.999 * std::sqrt(u(rng)), a = 2.0 * M_PI * u(rng);
        p.row(v) << r * std::cos(a), r * std::sin(a), 2.0 * u(rng) - 1.0;
    }
    return p;
}

}  // namespace

void runEffdBenchmarks(const std::vector<std::string>& filters) {
    if (!wanted(filters, "effd_freeze_1m") && !wanted(filters, "effd_eval_1m") && !wanted(filters, "effd_drag_step")) return;
    LatticeNet cylinder;
    if (Status s = makeCylinderNet(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 12, 1}, {2, 2}, cylinder); !s) {
        printError(std::cout, "effd", s.message);
        return;
    }
    LatticeSettings settings;
    settings.volume = std::make_shared<const LatticeNet>(cylinder);
    const int n = 1000000;
    const Positions points = pointsInCylinder(n);
    Lattice lattice;
    makeLatticeInBox(settings, {}, {}, lattice);
    Embedding embedding;
    if (wanted(filters, "effd_freeze_1m") || wanted(filters, "effd_eval_1m")) {
        const double ms = medianMs(3, [&] { embedVertices(lattice, points, embedding); });
        char extra[160];
        std::snprintf(extra, sizeof extra, "\"inside\": %d, \"chunks\": %d, \"control_points\": %d", embedding.insideCount(),
                      cylinder.chunkCount(), lattice.controlPointCount());
        if (wanted(filters, "effd_freeze_1m")) printCase("effd_freeze_1m", n, ms, extra);
    }
    if (wanted(filters, "effd_eval_1m") || wanted(filters, "box_eval_1m")) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> d(-0.05, 0.05);
        Lattice moved = lattice;
        for (int c = 0; c < moved.controlPointCount(); ++c) moved.displacement.row(c) << d(rng), d(rng), d(rng);
        for (const auto& group : cylinder.weldGroups)
            for (int s : group) moved.displacement.row(s) = moved.displacement.row(group[0]);
        Positions positions = points;
        const double effdMs = medianMs(9, [&] { evaluateAll(moved, embedding, positions); });
        // The box lattice of the same control point count per axis and degrees, around the same points.
        LatticeSettings box;
        box.resolution = cylinder.count;
        box.degree = cylinder.degree;
        box.padding = 0.0;
        Lattice boxLattice;
        makeLattice(box, points, boxLattice);
        for (int c = 0; c < boxLattice.controlPointCount(); ++c) boxLattice.displacement.row(c) << d(rng), d(rng), d(rng);
        const Embedding boxEmbedding = embedVertices(boxLattice, points);
        const double boxMs = medianMs(9, [&] { evaluateAll(boxLattice, boxEmbedding, positions); });
        char extra[200];
        std::snprintf(extra, sizeof extra, "\"box_eval_1m_ms\": %.2f, \"ratio_to_box\": %.2f, \"rational\": true", boxMs, effdMs / boxMs);
        printCase("effd_eval_1m", n, effdMs, extra);
    }
    if (wanted(filters, "effd_drag_step")) {
        // A 100k-point cylinder of points as a mesh without triangles, frozen in the cylinder; one mouse move.
        const Positions mesh = pointsInCylinder(100000);
        Session session;
        LatticeSettings start;
        start.resolution = {4, 4, 4};
        session.setMesh(mesh, Triangles(0, 3), start);
        OpReport report;
        session.tools().add({"cylinder", std::make_shared<const LatticeNet>(cylinder)}, report);
        session.tools().freeze(0, 0, report);
        const int vertex = 12345;
        const Eigen::Vector3d from = session.mesh().positions.row(vertex).transpose();
        session.stroke().beginAt({from}, {false}, BrushSettings{});
        int step = 0;
        const double ms = medianMs(15, [&] {
            ++step;
            session.stroke().update({from + Eigen::Vector3d(0.001 * step, 0.0005 * step, 0.0)}, report);
        });
        session.stroke().end();
        char extra[200];
        std::snprintf(extra, sizeof extra, "\"vertices_moved\": %d, \"injectivity_ms\": %.3f, \"status\": \"%s\"", report.verticesMoved,
                      report.injectivityMs, opStatusName(report.status));
        printCase("effd_drag_step", 100000, ms, extra);
    }
}

}  // namespace sculpt::bench
