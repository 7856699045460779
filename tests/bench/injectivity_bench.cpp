// sculpt_bench cases for the injectivity tests. The deformations are made the way the Session makes them:
// direct manipulations (Hu et al. 2001 eq. 7) of a few surface-like points, so the moved control points
// and the cells they influence are those of a real drag.
#include "injectivity_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>

#include "bench_support.h"
#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"

namespace sculpt::bench {

namespace {

using namespace sculpt::core;

bool wanted(const std::vector<std::string>& filters, const std::string& name) {
    if (filters.empty()) return true;
    for (const std::string& f : filters)
        if (name.find(f) != std::string::npos) return true;
    return false;
}

Lattice unitCubicLattice(int resolution) {
    LatticeSettings settings;
    settings.resolution = {resolution, resolution, resolution};
    settings.padding = 0.0;
    Positions corners(2, 3);
    corners << 0, 0, 0, 1, 1, 1;
    Lattice lattice;
    makeLattice(settings, corners, lattice);
    return lattice;
}

// Three drags of points near the top of the box: a bump pulled up, a dent pushed in, a sideways pull, each
// moving its point by about `cells` lattice cells. Returns the control points moved.
std::vector<int> applyRealisticDrags(Lattice& lattice, double cells) {
    const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> drags = {
        {{0.5, 0.5, 0.8}, {0.0, 0.0, 1.0}},
        {{0.3, 0.6, 0.75}, {0.0, 0.2, -0.7}},
        {{0.7, 0.35, 0.7}, {0.6, -0.25, 0.15}},
    };
    const Eigen::Vector3d cell =
        (lattice.boxMax - lattice.boxMin)
            .cwiseQuotient(Eigen::Vector3d(lattice.axes[0].spans, lattice.axes[1].spans, lattice.axes[2].spans));
    std::vector<int> moved;
    for (const auto& [params, move] : drags) {
        Eigen::MatrixX3d displacement(1, 3);
        displacement.row(0) = (cells * move.cwiseProduct(cell)).transpose();
        const DirectManipulationResult solved = directManipulation(lattice, {params}, displacement);
        applyControlDelta(lattice, solved.delta);
        moved.insert(moved.end(), solved.delta.indices.begin(), solved.delta.indices.end());
    }
    std::sort(moved.begin(), moved.end());
    moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
    return moved;
}

void denseDisplacement(Lattice& lattice, double fractionOfCell) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    const Eigen::Vector3d cell =
        (lattice.boxMax - lattice.boxMin)
            .cwiseQuotient(Eigen::Vector3d(lattice.axes[0].spans, lattice.axes[1].spans, lattice.axes[2].spans));
    for (int c = 0; c < lattice.controlPointCount(); ++c)
        for (int a = 0; a < 3; ++a) lattice.displacement(c, a) = fractionOfCell * cell[a] * d(rng);
}

// Median via bench::medianMs, plus the minimum of the same runs (the machine is shared: the minimum is the
// better estimate of the cost, the median of what a user sees).
void timeCase(const std::string& name, int runs, const Lattice& lattice, long long n,
              const std::function<InjectivityResult()>& check) {
    double minimum = 1e300;
    InjectivityResult last;
    const double median = medianMs(runs, [&] {
        const auto start = std::chrono::steady_clock::now();
        last = check();
        minimum = std::min(minimum,
                           std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    });
    char extra[256];
    std::snprintf(extra, sizeof extra,
                  "\"min_ms\": %.4f, \"verdict\": \"%s\", \"cells\": %d, \"cells_deformed\": %d, \"boxes\": %lld, "
                  "\"degree\": %d",
                  minimum, injectivityVerdictName(last.verdict), last.cellsChecked, last.cellsDeformed,
                  last.boxesExamined, lattice.degree[0]);
    printCase(name, n, median, extra);
}

}  // namespace

void runInjectivityBenchmarks(const std::vector<std::string>& filters) {
    const int runs = 21;
    // Drags of half a cell (the conic test certifies them: the per-drag case the Session meets after its
    // adaptive halving), and every control point moved by up to 5% of a cell.
    const double kDragCells16 = 0.5, kDragCells8 = 0.5, kDenseCells = 0.05;
    {
        Lattice lattice = unitCubicLattice(16);
        const std::vector<int> moved = applyRealisticDrags(lattice, kDragCells16);
        const std::vector<int> cells = cellsInfluencedBy(lattice, moved);
        if (wanted(filters, "inject_conic_16"))
            timeCase("inject_conic_16", runs, lattice, lattice.cellCount(),
                     [&] { return checkInjectivityConic(lattice); });
        if (wanted(filters, "inject_conic_16_cells"))
            timeCase("inject_conic_16_cells", runs, lattice, static_cast<long long>(cells.size()),
                     [&] { return checkInjectivityConic(lattice, cells); });
        if (wanted(filters, "inject_conic_16_dense")) {
            Lattice dense = unitCubicLattice(16);
            denseDisplacement(dense, kDenseCells);
            timeCase("inject_conic_16_dense", runs, dense, dense.cellCount(),
                     [&] { return checkInjectivityConic(dense); });
        }
    }
    {
        Lattice lattice = unitCubicLattice(8);
        applyRealisticDrags(lattice, kDragCells8);
        if (wanted(filters, "inject_exact_8"))
            timeCase("inject_exact_8", runs, lattice, lattice.cellCount(),
                     [&] { return checkInjectivityExact(lattice); });
        if (wanted(filters, "inject_exact_8_fold")) {  // drags too long for one step: the fold is found and located
            Lattice folded = unitCubicLattice(8);
            applyRealisticDrags(folded, 1.5);
            timeCase("inject_exact_8_fold", runs, folded, folded.cellCount(),
                     [&] { return checkInjectivityExact(folded); });
        }
        if (wanted(filters, "inject_exact_8_dense")) {
            Lattice dense = unitCubicLattice(8);
            denseDisplacement(dense, kDenseCells);
            timeCase("inject_exact_8_dense", runs, dense, dense.cellCount(),
                     [&] { return checkInjectivityExact(dense); });
        }
    }
    if (wanted(filters, "inject_exact_cylinder")) {
        // A net lattice (rational (2,2,2) chunks, the axis collapsed): every control point moved by up to 5% of
        // the radius, welded points together, so all 24 chunks are checked, 12 of them on the axis.
        LatticeNet net;
        makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 6, 2}, {2, 2}, net);
        LatticeSettings settings;
        settings.volume = std::make_shared<LatticeNet>(net);
        Lattice lattice;
        makeLatticeInBox(settings, {}, {}, lattice);
        denseDisplacement(lattice, 0.0);
        std::mt19937 rng(6);
        std::uniform_real_distribution<double> d(-0.05, 0.05);
        for (int c = 0; c < lattice.controlPointCount(); ++c)
            if (lattice.representative(c) == c) lattice.displacement.row(c) = Eigen::RowVector3d(d(rng), d(rng), d(rng));
        for (int c = 0; c < lattice.controlPointCount(); ++c)
            lattice.displacement.row(c) = lattice.displacement.row(lattice.representative(c)).eval();
        timeCase("inject_exact_cylinder", runs, lattice, lattice.cellCount(), [&] { return checkInjectivityExact(lattice); });
    }
}

}  // namespace sculpt::bench
