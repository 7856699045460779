// Weighted T-spline tools in the session (Song & Yang 2005, "Free-form deformation with weighted T-spline",
// seed 002): setting one up around the mesh (sec. 4, Fig. 9-10; sec. 6 steps 1-3) and subdividing its cells
// locally (sec. 6 step 2, Fig. 11). Both are made of the lattice-tool commands (tool_library.h), so
// undo, redo and recordings treat them as any other tool change or freeze.
#include "core/session/session.h"
#include "core/session/session_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sculpt::core {

namespace {

std::string countsText(const std::array<int, 3>& c) {
    return std::to_string(c[0]) + "x" + std::to_string(c[1]) + "x" + std::to_string(c[2]);
}

}  // namespace

Status TSplineTools::setup(const TSplineSetup& setup, OpReport& report) {
    const auto start = detail::Clock::now();
    report = OpReport{};
    report.op = "setup_tspline";
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    const TSplineOctreeSettings& octree = setup.octree;
    if (octree.octree.depth < 1 || octree.octree.depth > kMaxTSplineSetupDepth)
        return Status::error("depth: expected 1 to " + std::to_string(kMaxTSplineSetupDepth) + " levels of octree subdivision, got " +
                             std::to_string(octree.octree.depth));
    for (int a = 0; a < 3; ++a)
        if (octree.octree.rootCount[a] < 1 || octree.octree.rootCount[a] > kMaxTSplineSetupRootCells)
            return Status::error("root: expected 1 to " + std::to_string(kMaxTSplineSetupRootCells) + " root cells per axis, got " +
                                 countsText(octree.octree.rootCount));
    if (!std::isfinite(octree.weightRatio) || !(octree.weightRatio > 0.0))
        return Status::error("weight_ratio: expected a finite number > 0 (heavy : light weights, 100 in the paper)");
    // Sec. 4 / sec. 6 step 1: the initial region of the model to be deformed.
    Eigen::AlignedBox3d region;
    if (setup.hasRegion) {
        if (!setup.regionMin.allFinite() || !setup.regionMax.allFinite()) return Status::error("region: expected finite \"min\" and \"max\"");
        if (!(setup.regionMin.array() < setup.regionMax.array()).all())
            return Status::error("region: \"min\" must be below \"max\" on every axis (the region is empty)");
        region = Eigen::AlignedBox3d(setup.regionMin, setup.regionMax);
    } else {
        if (!std::isfinite(octree.padding) || !(octree.padding >= 0.0)) return Status::error("padding: expected a finite number >= 0");
        if (Status s = paddedPointBounds(s_.mesh_.positions, octree.padding, region); !s) return s;
    }
    int inside = 0;
    for (Eigen::Index v = 0; v < s_.mesh_.positions.rows(); ++v) inside += region.contains(s_.mesh_.positions.row(v).transpose());
    if (inside == 0)
        return Status::error("region: holds none of the mesh's " + std::to_string(s_.mesh_.positions.rows()) + " vertices (" +
                             detail::vectorText(region.min()) + " to " + detail::vectorText(region.max()) + ")");
    std::shared_ptr<const TSplineVolume> volume;
    TSplineWeightOutcome weights;
    if (Status s = makeOctreeTSplineVolumeInBox(s_.mesh_.positions, region, octree, volume, &weights); !s) return s;
    const std::string name = setup.name.empty() ? std::string("tspline") : setup.name;
    const int index = static_cast<int>(s_.tools_.list.size());
    const int firstOperation = s_.history_.cursor();
    OpReport added;
    if (Status s = s_.tools().add({name, volume}, added); !s) return s;
    // The heavy points are those at the largest weight (sec. 4's non-empty cells); the weights fall off from
    // them by the weight step per ring of the control net (balancedTSplineWeights).
    // A ratio below 1 makes them the lightest (the far ones keep weight 1 either way).
    const std::vector<double>& w = volume->controlWeights();
    const double extreme = w.empty()                 ? 1.0
                           : weights.weightRatio >= 1.0 ? *std::max_element(w.begin(), w.end())
                                                        : *std::min_element(w.begin(), w.end());
    int heavy = 0;
    for (double x : w) heavy += x == extreme && extreme != 1.0;
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%g", weights.weightRatio);
    std::string summary = "T-spline " + name + ": " + std::to_string(volume->lattice().cells.size()) + " cells at depth " +
                          std::to_string(octree.octree.depth) + ", " + std::to_string(volume->controlPointCount()) + " control points (" +
                          std::to_string(heavy) + " of them weighted " + ratio + ":1)";
    if (weights.ratioReduced) summary += " [" + weights.message + "]";
    if (!setup.freeze) {
        report = added;
        report.op = "setup_tspline";
        report.reason = "added " + summary;
        report.wallMs = detail::millisecondsSince(start);
        return Status::success();
    }
    const Status frozen = s_.tools().freeze(index, 0, report);
    if (!frozen || report.status != OpStatus::Applied) {
        // note: the tool was added for this freeze only; take it back so a failed set-up changes nothing.
        OpReport undone;
        s_.undo(undone);
        if (!frozen) return frozen;
        report.op = "setup_tspline";
        return Status::success();
    }
    // One history entry, as the user asked for one thing: undo takes back the freeze and the tool together.
    if (Status s = s_.groupOperations(firstOperation, "set up T-spline " + name); !s) return s;
    report.op = "setup_tspline";
    report.reason = summary + "; " + report.reason;
    report.wallMs = detail::millisecondsSince(start);
    return Status::success();
}

Status TSplineTools::subdivideCells(int index, const std::vector<int>& cells, const std::vector<Eigen::Vector3d>& at, bool balance,
                                      OpReport& report) {
    const auto start = detail::Clock::now();
    report = OpReport{};
    report.op = "subdivide_cells";
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    if (index < 0 || index >= static_cast<int>(s_.tools_.list.size())) return Status::error("index: there is no lattice " + std::to_string(index));
    const LatticeTool& tool = s_.tools_.list[static_cast<size_t>(index)];
    if (index == s_.tools_.frozen)
        return Status::error("lattice " + tool.name + " is frozen: unfreeze it before subdividing its cells (the vertices' parameters would change)");
    const TSplineVolume* tspline = tool.volume ? tool.volume->tsplineVolume() : nullptr;
    if (!tspline)
        return Status::error("lattice " + tool.name + " is a " + tool.volume->kindName() +
                             ", not a T-spline: only T-spline lattices have cells to subdivide (edit_lattice refines nets)");
    const TSplineBasis& basis = tspline->basis();
    const int cellCount = static_cast<int>(basis.lattice.cells.size());
    std::vector<int> chosen;
    for (size_t c = 0; c < cells.size(); ++c) {
        if (cells[c] < 0 || cells[c] >= cellCount)
            return Status::error("cells[" + std::to_string(c) + "]: cell " + std::to_string(cells[c]) + " does not exist (lattice " + tool.name +
                                 " has cells 0 to " + std::to_string(cellCount - 1) + ")");
        chosen.push_back(cells[c]);
    }
    for (size_t p = 0; p < at.size(); ++p) {
        Eigen::Vector3d t, local;
        const int element = at[p].allFinite() && tspline->freeze(at[p], t) ? basis.elementOf(t, local) : -1;
        if (element < 0)
            return Status::error("at[" + std::to_string(p) + "]: " + detail::vectorText(at[p]) + " is outside lattice " + tool.name);
        chosen.push_back(basis.elementCell[static_cast<size_t>(element)]);
    }
    if (chosen.empty()) return Status::error("no cells to subdivide: give \"cells\" or \"at\"");
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
    std::shared_ptr<const TSplineVolume> finer;
    TSplineWeightOutcome weights;
    if (Status s = subdivideTSplineVolume(*tspline, chosen, balance, s_.mesh_.positions, finer, &weights); !s)
        return Status::error("lattice " + tool.name + ": " + s.message);
    const std::string name = tool.name;
    const size_t before = basis.lattice.cells.size();
    const int pointsBefore = tspline->controlPointCount();
    if (Status s = s_.tools().edit(index, {name, finer}, report); !s) return s;
    report.op = "subdivide_cells";
    Operation& operation = s_.history_.last();
    operation.label = "subdivide " + std::to_string(chosen.size()) + (chosen.size() == 1 ? " cell" : " cells") + " of lattice " + name;
    s_.history_.lastJournaled().label = operation.label;
    report.reason = "lattice " + name + ": " + std::to_string(before) + " -> " + std::to_string(finer->lattice().cells.size()) + " cells, " +
                    std::to_string(pointsBefore) + " -> " + std::to_string(finer->controlPointCount()) + " control points";
    if (weights.ratioReduced) report.reason += " [" + weights.message + "]";
    report.wallMs = detail::millisecondsSince(start);
    return Status::success();
}

}  // namespace sculpt::core
