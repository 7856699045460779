#include "render/overlay_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "render/palette.h"

namespace sculpt::render {

namespace {

void appendPoint(std::vector<float>& out, const LocalFrame& frame, const Positions& points, Eigen::Index row) {
    const glm::dvec3 local = frame.toLocal(glm::dvec3(points(row, 0), points(row, 1), points(row, 2)));
    out.insert(out.end(), {float(local.x), float(local.y), float(local.z)});
}

void appendColor(std::vector<float>& out, const Rgba& color) {
    out.insert(out.end(), {color.r, color.g, color.b, color.a});
}

void appendAxisLines(std::vector<float>& out, const LocalFrame& frame, const std::vector<ConstraintView::AxisLine>& lines) {
    for (const ConstraintView::AxisLine& line : lines) {
        for (const Eigen::Vector3d& end : {line.from, line.to}) {
            const glm::dvec3 local = frame.toLocal(glm::dvec3(end.x(), end.y(), end.z()));
            out.insert(out.end(), {float(local.x), float(local.y), float(local.z)});
        }
        appendColor(out, kAxisColors[line.axis]);
        appendColor(out, kAxisColors[line.axis]);
    }
}

}  // namespace

Status checkFinite(const Positions& points, const char* what) {
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (!points.row(i).allFinite())
            return Status::error(std::string(what) + " row " + std::to_string(i) + " is not finite (NaN or infinity)");
    return Status::success();
}

Status buildLatticeInstances(const LatticeView& lattice, const LocalFrame& frame, std::vector<float>& edgesOut,
                             std::vector<float>& markersOut, Bounds& boundsOut) {
    std::vector<float> edges, points;
    Bounds bounds;
    for (const std::vector<Positions>* polylines : {&lattice.curves, &lattice.toolCurves, &lattice.chosenCells})
        for (const Positions& curve : *polylines)
            if (Status status = checkFinite(curve, polylines == &lattice.curves      ? "lattice curve point"
                                                   : polylines == &lattice.toolCurves ? "lattice tool curve point"
                                                                                      : "chosen cell edge point");
                !status)
                return status;
    if (Status status = checkFinite(lattice.tJunctions, "T-junction"); !status) return status;
    // T-junctions first: the control points the user works with draw over them.
    for (Eigen::Index j = 0; j < lattice.tJunctions.rows(); ++j) {
        appendPoint(points, frame, lattice.tJunctions, j);
        appendColor(points, kTJunctionColor);
        // A diamond at full strength at any depth (style 2: not faded, the back of a lattice is where its
        // T-junctions often are), shrinking where markers crowd like the plain control points.
        points.insert(points.end(), {kTJunctionSize, 2.0f, 2.0f});
    }
    if (lattice.nu != 0 || lattice.nv != 0 || lattice.nw != 0) {
        if (lattice.nu < 1 || lattice.nv < 1 || lattice.nw < 1)
            return Status::error("lattice size " + std::to_string(lattice.nu) + " x " + std::to_string(lattice.nv) +
                                 " x " + std::to_string(lattice.nw) + ": each dimension must be at least 1");
        const Eigen::Index count = Eigen::Index(lattice.nu) * lattice.nv * lattice.nw;
        if (lattice.controlPoints.rows() != count)
            return Status::error("lattice " + std::to_string(lattice.nu) + " x " + std::to_string(lattice.nv) +
                                 " x " + std::to_string(lattice.nw) + " needs " + std::to_string(count) +
                                 " control points, got " + std::to_string(lattice.controlPoints.rows()));
        if (!lattice.selected.empty() && lattice.selected.size() != size_t(count))
            return Status::error("lattice selection has " + std::to_string(lattice.selected.size()) +
                                 " flags for " + std::to_string(count) + " control points");
        if (!lattice.pinned.empty() && lattice.pinned.size() != size_t(count))
            return Status::error("lattice pin flags: " + std::to_string(lattice.pinned.size()) + " for " +
                                 std::to_string(count) + " control points");
        if (!lattice.drawn.empty() && lattice.drawn.size() != size_t(count))
            return Status::error("lattice drawn flags: " + std::to_string(lattice.drawn.size()) + " for " +
                                 std::to_string(count) + " control points");
        for (const std::array<int, 2>& edge : lattice.netEdges)
            if (edge[0] < 0 || edge[1] < 0 || edge[0] >= count || edge[1] >= count)
                return Status::error("lattice net edge " + std::to_string(edge[0]) + "-" + std::to_string(edge[1]) +
                                     " names a control point outside 0.." + std::to_string(count - 1));
        if (Status status = checkFinite(lattice.controlPoints, "lattice control point"); !status) return status;

        const auto isSelected = [&](Eigen::Index p) { return !lattice.selected.empty() && lattice.selected[p]; };
        const auto isPinned = [&](Eigen::Index p) { return !lattice.pinned.empty() && lattice.pinned[p]; };
        const auto isDrawn = [&](Eigen::Index p) { return lattice.drawn.empty() || lattice.drawn[size_t(p)]; };
        const auto edgeColor = [&](Eigen::Index p) {
            return isSelected(p) ? kSelectedEdgeColor : isPinned(p) ? kPinnedEdgeColor : kLatticeEdgeColor;
        };
        const auto index = [&](int i, int j, int k) { return Eigen::Index(i) + lattice.nu * (Eigen::Index(j) + Eigen::Index(lattice.nv) * k); };
        const int nu = lattice.nu, nv = lattice.nv, nw = lattice.nw;
        // A net lattice (explicit edges or curves) is not a grid: outerOnly's face rule does not apply, the
        // caller's `drawn` flags say what shows.
        const bool grid = lattice.netEdges.empty() && lattice.curves.empty();
        const bool outerOnly = lattice.outerOnly && grid;
        // note: an edge lies on an outer face when one of the two coordinates it does not run along is at the
        // face (its end points alone would also admit the interior edges from a face inwards).
        const auto onOuterFace = [&](int a, int na, int b, int nb) {
            return !outerOnly || a == 0 || a == na - 1 || b == 0 || b == nb - 1;
        };
        std::vector<std::uint8_t> shown(size_t(count), 1);
        if (outerOnly)
            for (int k = 0; k < nw; ++k)
                for (int j = 0; j < nv; ++j)
                    for (int i = 0; i < nu; ++i)
                        shown[size_t(index(i, j, k))] = onLatticeBoundary(i, j, k, nu, nv, nw);
        const auto addEdge = [&](Eigen::Index a, Eigen::Index b) {
            if (!lattice.edgesOfHiddenPoints && (!isDrawn(a) || !isDrawn(b))) return;
            appendPoint(edges, frame, lattice.controlPoints, a);
            appendPoint(edges, frame, lattice.controlPoints, b);
            appendColor(edges, edgeColor(a));
            appendColor(edges, edgeColor(b));
        };
        if (grid) {
            for (int k = 0; k < lattice.nw; ++k)
                for (int j = 0; j < lattice.nv; ++j)
                    for (int i = 0; i < lattice.nu; ++i) {
                        const Eigen::Index p = index(i, j, k);
                        if (i + 1 < nu && onOuterFace(j, nv, k, nw)) addEdge(p, index(i + 1, j, k));
                        if (j + 1 < nv && onOuterFace(i, nu, k, nw)) addEdge(p, index(i, j + 1, k));
                        if (k + 1 < nw && onOuterFace(i, nu, j, nv)) addEdge(p, index(i, j, k + 1));
                    }
        } else {
            for (const std::array<int, 2>& edge : lattice.netEdges) addEdge(edge[0], edge[1]);
        }
        // Plain points first, then pinned, then selected, so the ones the user works with draw on top.
        for (int pass = 0; pass < 3; ++pass)
            for (Eigen::Index p = 0; p < count; ++p) {
                const int kind = isSelected(p) ? 2 : isPinned(p) ? 1 : 0;
                if (kind != pass || !isDrawn(p) || (kind != 2 && !shown[size_t(p)])) continue;
                appendPoint(points, frame, lattice.controlPoints, p);
                appendColor(points, kind == 2 ? kSelectedPointColor : kind == 1 ? kPinnedPointColor : kControlPointColor);
                points.push_back(kind == 2 ? kSelectedPointSize : kind == 1 ? kPinnedPointSize : kControlPointSize);
                points.push_back(isPinned(p) ? 1.0f : 0.0f);  // pinned: square, even when selected
                points.push_back(kind == 2 ? 0.0f : 1.0f);    // the selection stays at full strength at any depth
            }
        bounds = boundsOf(lattice.controlPoints);
    }
    if (lattice.tJunctions.rows() > 0) bounds.add(boundsOf(lattice.tJunctions));
    // Polylines: one segment per pair of consecutive samples.
    const auto addPolylines = [&](const std::vector<Positions>& polylines, const Rgba& color) {
        for (const Positions& curve : polylines) {
            for (Eigen::Index r = 0; r + 1 < curve.rows(); ++r) {
                appendPoint(edges, frame, curve, r);
                appendPoint(edges, frame, curve, r + 1);
                appendColor(edges, color);
                appendColor(edges, color);
            }
            bounds.add(boundsOf(curve));
        }
    };
    addPolylines(lattice.curves, kLatticeCurveColor);
    addPolylines(lattice.toolCurves, kLatticeToolColor);
    addPolylines(lattice.chosenCells, kChosenCellColor);
    edgesOut.swap(edges);
    markersOut.swap(points);
    boundsOut = bounds;
    return Status::success();
}

float crowdedMarkerScale(const std::vector<glm::vec2>& pixels, float diameter) {
    if (pixels.size() < 2 || !(diameter > 0.0f)) return 1.0f;
    glm::vec2 lo = pixels.front(), hi = lo;
    for (const glm::vec2& p : pixels) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    // Cells one marker wide over the region the markers span; a cell holds a marker or not. note: distinct
    // cells, not a count of markers, so markers drawn over each other (a grid seen along an axis) crowd nothing.
    const int columns = static_cast<int>(std::ceil((hi.x - lo.x) / diameter)) + 1;
    const int rows = static_cast<int>(std::ceil((hi.y - lo.y) / diameter)) + 1;
    std::vector<std::uint8_t> occupied(static_cast<size_t>(columns) * static_cast<size_t>(rows), 0);
    const auto cellOf = [&](const glm::vec2& p) {
        return glm::ivec2(std::min(columns - 1, static_cast<int>((p.x - lo.x) / diameter + 0.5f)),
                          std::min(rows - 1, static_cast<int>((p.y - lo.y) / diameter + 0.5f)));
    };
    const auto at = [&](int column, int row) -> std::uint8_t& {
        return occupied[static_cast<size_t>(row) * static_cast<size_t>(columns) + static_cast<size_t>(column)];
    };
    for (const glm::vec2& p : pixels) at(cellOf(p).x, cellOf(p).y) = 1;
    // Around each marker, the share of the 24 cells within two diameters (a 5 x 5 block less its own) that
    // hold another; the mean over the markers is how crowded they are where they are (a dense core counts by
    // its many markers, however much empty box surrounds it).
    constexpr int kReach = 2;
    constexpr double kNeighbourCells = (2 * kReach + 1) * (2 * kReach + 1) - 1;
    double sum = 0.0;
    for (const glm::vec2& p : pixels) {
        const glm::ivec2 cell = cellOf(p);
        int neighbours = 0;
        for (int row = std::max(0, cell.y - kReach); row <= std::min(rows - 1, cell.y + kReach); ++row)
            for (int column = std::max(0, cell.x - kReach); column <= std::min(columns - 1, cell.x + kReach); ++column)
                neighbours += at(column, row);
        sum += (neighbours - 1) / kNeighbourCells;  // less its own cell
    }
    const double crowding = sum / static_cast<double>(pixels.size());
    if (crowding <= kCrowdedMarkerShare) return 1.0f;
    return std::max(kMinCrowdedMarkerScale, static_cast<float>(std::sqrt(kCrowdedMarkerShare / crowding)));
}

Status buildConstraintInstances(const ConstraintView& constraints, const LocalFrame& frame,
                                std::vector<float>& segments, std::vector<float>& markers) {
    if (constraints.sources.rows() != constraints.targets.rows())
        return Status::error("constraints: " + std::to_string(constraints.sources.rows()) + " sources but " +
                             std::to_string(constraints.targets.rows()) + " targets");
    if (Status status = checkFinite(constraints.sources, "constraint source"); !status) return status;
    if (Status status = checkFinite(constraints.targets, "constraint target"); !status) return status;
    if (Status status = checkFinite(constraints.handles, "handle"); !status) return status;
    if (Status status = checkFinite(constraints.pins, "pin"); !status) return status;
    if (Status status = checkFinite(constraints.outline, "brush outline point"); !status) return status;
    for (const ConstraintView::AxisLine& line : constraints.axisLines)
        if (!line.from.allFinite() || !line.to.allFinite() || line.axis < 0 || line.axis > 2)
            return Status::error("axis line: non-finite end or axis " + std::to_string(line.axis) + " (0, 1 or 2)");
    const Eigen::Index loop = constraints.outlineLoop > 0 ? constraints.outlineLoop : constraints.outline.rows();
    if (loop > 0 && constraints.outline.rows() % loop != 0)
        return Status::error("brush outline: " + std::to_string(constraints.outline.rows()) + " points, not a multiple of its loops' " +
                             std::to_string(loop));
    std::vector<float> lines, points;
    for (Eigen::Index c = 0; c < constraints.outline.rows(); ++c) {
        appendPoint(lines, frame, constraints.outline, c);
        appendPoint(lines, frame, constraints.outline, c - c % loop + (c % loop + 1) % loop);  // the next point round its loop
        appendColor(lines, kBrushOutlineColor);
        appendColor(lines, kBrushOutlineColor);
    }
    for (Eigen::Index c = 0; c < constraints.sources.rows(); ++c) {
        appendPoint(lines, frame, constraints.sources, c);
        appendPoint(lines, frame, constraints.targets, c);
        appendColor(lines, kSourceColor);
        appendColor(lines, kTargetColor);
    }
    appendAxisLines(lines, frame, constraints.axisLines);
    const auto appendMarkers = [&points, &frame](const Positions& at, const Rgba& color, float shape) {
        for (Eigen::Index c = 0; c < at.rows(); ++c) {
            appendPoint(points, frame, at, c);
            appendColor(points, color);
            points.insert(points.end(), {kHandleSize, shape, 0.0f});  // no depth fade: always on top
        }
    };
    appendMarkers(constraints.sources, kSourceColor, 0.0f);  // shape 0: disc
    appendMarkers(constraints.targets, kTargetColor, 0.0f);
    appendMarkers(constraints.handles, kSourceColor, 0.0f);
    appendMarkers(constraints.pins, kSurfacePinColor, 1.0f);  // shape 1: square
    segments.swap(lines);
    markers.swap(points);
    return Status::success();
}

}  // namespace sculpt::render
