// Editing a lattice that is not frozen (Coquillart 1990, EFFD, 3.1.4): moving and merging points, inserting
// points by knot insertion (Boehm 1980; Piegl & Tiller, The NURBS Book, A5.1, on homogeneous points) and
// removing slices.
#include "core/volume/lattice_edit.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <utility>

namespace sculpt::core {

namespace {

Status checkSlot(const LatticeNet& net, int slot) {
    if (slot < 0 || slot >= net.slotCount())
        return Status::error("slot " + std::to_string(slot) + " is out of range (the lattice has " + std::to_string(net.slotCount()) +
                             " points)");
    return Status::success();
}

Status checkAxis(int axis) {
    if (axis < 0 || axis > 2) return Status::error("axis " + std::to_string(axis) + " is out of range (0 u, 1 v, 2 w)");
    return Status::success();
}

// Finishes `net` (validates it, fills its derived data) and moves it to `out`; a failure says what the edit
// was ("moving slots ...") before finishLatticeNet's reason.
Status finishEdit(LatticeNet& net, const std::string& what, LatticeNet& out) {
    if (Status s = finishLatticeNet(net); !s) return Status::error(what + " leaves an invalid lattice: " + s.message);
    out = std::move(net);
    return Status::success();
}

std::string slotList(const std::vector<int>& slots) {
    std::string s;
    for (size_t i = 0; i < slots.size() && i < 8; ++i) s += (i ? ", " : "") + std::to_string(slots[i]);
    if (slots.size() > 8) s += ", ...";
    return s;
}

// The knot-insertion matrix of one axis: new control points = A * old control points (A is count' x count,
// rows sum to 1, entries >= 0), for inserting `inserted` (knot parameters, any order, repeats allowed) into
// the clamped knot vector `knots` of `degree`. Boehm's algorithm (The NURBS Book, A5.1 with r = 1, eq. 5.15,
// which holds for a knot already present), run on the rows of the identity, one knot at a time. `knots`
// becomes the refined knot vector.
Eigen::MatrixXd insertionMatrix(std::vector<double>& knots, int degree, std::vector<double> inserted) {
    const int p = degree;
    std::sort(inserted.begin(), inserted.end());
    const int count = static_cast<int>(knots.size()) - p - 1;
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(count, count);
    for (const double u : inserted) {
        // k: the last knot index with knots[k] <= u (u lies in [knots[k], knots[k+1]), knots[k+1] > u).
        const int k = static_cast<int>(std::upper_bound(knots.begin(), knots.end(), u) - knots.begin()) - 1;
        const int n = static_cast<int>(a.rows());
        Eigen::MatrixXd next(n + 1, a.cols());
        for (int i = 0; i <= n; ++i) {
            if (i <= k - p) {
                next.row(i) = a.row(i);
            } else if (i <= k) {
                // alpha_i = (u - u_i) / (u_{i+p} - u_i); u_{i+p} >= u_{k+1} > u >= u_i (0 where u_i = u: a repeated knot).
                const double alpha = (u - knots[i]) / (knots[i + p] - knots[i]);
                next.row(i) = alpha * a.row(i) + (1.0 - alpha) * a.row(i - 1);
            } else {
                next.row(i) = a.row(i - 1);
            }
        }
        a = std::move(next);
        knots.insert(knots.begin() + k + 1, u);
    }
    return a;
}

// The net with axis `axis` refined by the knot-insertion matrix `a` (new count x old count) to the knot vector
// `knots`: new points are the combinations `a` gives of the old homogeneous points (W P, W) per line along
// the axis (The NURBS Book, 5.2: knot insertion of a NURBS curve is done on Pw), so Q is unchanged.
Status refineAxisBy(const LatticeNet& net, int axis, const Eigen::MatrixXd& a, std::vector<double> knots, const std::string& what,
                    LatticeNet& out) {
    const int newCount = static_cast<int>(a.rows());
    if (newCount > kMaxControlPointsPerAxis)
        return Status::error(what + " would make " + std::to_string(newCount) + " control points along " + parameterAxisName(axis) + " (at most " +
                             std::to_string(kMaxControlPointsPerAxis) + ")");
    LatticeNet refined;
    refined.kind = net.kind;
    refined.count = net.count;
    refined.count[axis] = newCount;
    refined.degree = net.degree;
    refined.multiplicity = net.multiplicity;
    refined.knots = net.knots;
    refined.knots[axis] = std::move(knots);  // finishLatticeNet drops it again where it is uniform
    const int n = refined.slotCount();
    refined.rest.resize(n, 3);
    refined.weights.resize(n);
    // Per new slot: its combination of old weld groups (group -> coefficient), for the structural welds below.
    std::vector<std::vector<std::pair<int, double>>> combination(n);
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    for (int ic = 0; ic < net.count[c]; ++ic)
        for (int ib = 0; ib < net.count[b]; ++ib) {
            auto oldSlot = [&](int i) {
                std::array<int, 3> ijk{};
                ijk[axis] = i, ijk[b] = ib, ijk[c] = ic;
                return net.slot(ijk[0], ijk[1], ijk[2]);
            };
            for (int t = 0; t < newCount; ++t) {
                std::array<int, 3> ijk{};
                ijk[axis] = t, ijk[b] = ib, ijk[c] = ic;
                const int slot = refined.slot(ijk[0], ijk[1], ijk[2]);
                Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
                double weight = 0.0;
                std::map<int, double> groups;
                for (int i = 0; i < net.count[axis]; ++i) {
                    const double coefficient = a(t, i);
                    if (coefficient == 0.0) continue;
                    const int s = oldSlot(i);
                    const double wa = coefficient * net.weights[static_cast<size_t>(s)];
                    weighted += wa * net.rest.row(s).transpose();
                    weight += wa;
                    groups[net.weldedTo[s]] += wa;
                }
                refined.rest.row(slot) = (weighted / weight).transpose();
                refined.weights[static_cast<size_t>(slot)] = weight;
                for (const auto& [group, wa] : groups) combination[slot].emplace_back(group, wa / weight);
            }
        }
    // Structural welds: new slots whose combinations of old groups are the same are one point for every
    // placement of the old points (so every deformation of the old net is one of the new net), and only those
    // are welded. Coincidence at rest is necessary for that, so it finds the candidates cheaply.
    LatticeNet candidates;
    candidates.rest = refined.rest;
    weldCoincidentSlots(candidates, 1e-9);
    auto sameCombination = [&](int s, int t) {
        const auto& x = combination[s];
        const auto& y = combination[t];
        if (x.size() != y.size()) return false;
        for (size_t e = 0; e < x.size(); ++e)
            if (x[e].first != y[e].first || std::abs(x[e].second - y[e].second) > 1e-12) return false;
        return true;
    };
    refined.weldedTo.resize(n);
    std::map<int, std::vector<int>> classes;  // candidate cluster -> representatives of its structural classes
    for (int s = 0; s < n; ++s) {  // ascending, so a class's first slot is its smallest
        refined.weldedTo[s] = s;
        auto& reps = classes[candidates.weldedTo[s]];
        for (int r : reps)
            if (sameCombination(r, s)) {
                refined.weldedTo[s] = r;
                refined.rest.row(s) = refined.rest.row(r);  // welded points are exactly one point
                break;
            }
        if (refined.weldedTo[s] == s) reps.push_back(s);
    }
    return finishEdit(refined, what, out);
}

}  // namespace

Status moveNetPoints(const LatticeNet& net, const std::vector<int>& slots, const Eigen::Vector3d& offset, LatticeNet& out) {
    if (slots.empty()) return Status::error("moving points needs at least one slot");
    for (int s : slots)
        if (Status st = checkSlot(net, s); !st) return st;
    if (!offset.allFinite()) return Status::error("the offset of a move must be finite");
    std::vector<char> moved(net.slotCount(), 0);
    for (int s : slots) moved[net.weldedTo[s]] = 1;
    LatticeNet edited = rawNetFields(net);
    // note: a weld group's slots are equal before the move and get the same offset, so they stay bitwise equal.
    for (int s = 0; s < net.slotCount(); ++s)
        if (moved[net.weldedTo[s]]) edited.rest.row(s) += offset.transpose();
    return finishEdit(edited, "moving slots " + slotList(slots), out);
}

Status mergeNetPoints(const LatticeNet& net, const std::vector<int>& slots, LatticeNet& out) {
    for (int s : slots)
        if (Status st = checkSlot(net, s); !st) return st;
    std::vector<int> groups;  // representatives of the distinct points merged
    for (int s : slots) groups.push_back(net.weldedTo[s]);
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    if (groups.size() < 2)
        return Status::error("merging needs at least 2 distinct points; slots " + slotList(slots) + " are " +
                             (groups.empty() ? std::string("none") : "all one point (weld group of slot " + std::to_string(groups[0]) + ")"));
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int g : groups) mean += net.rest.row(g).transpose();
    mean /= static_cast<double>(groups.size());
    std::vector<char> merged(net.slotCount(), 0);
    for (int g : groups) merged[g] = 1;
    LatticeNet edited = rawNetFields(net);
    // The merged group's representative is its smallest slot: the smallest of the groups' representatives.
    const int representative = groups.front();
    for (int s = 0; s < net.slotCount(); ++s)
        if (merged[net.weldedTo[s]]) {
            edited.weldedTo[s] = representative;
            edited.rest.row(s) = mean.transpose();
        }
    return finishEdit(edited, "merging slots " + slotList(slots), out);
}

Status refineNetAxis(const LatticeNet& net, int axis, LatticeNet& out) {
    if (Status s = checkAxis(axis); !s) return s;
    const SplineAxis& old = net.axes[axis];
    std::vector<double> midpoints;
    for (int span = 0; span < old.spans; ++span) {
        if (old.uniform()) {
            // note: (2 span + 1) / (2 spans) is the correctly rounded midpoint, as makeSplineAxis computes the
            // refined axis' knot j / (2 spans): the knot vectors agree exactly and the result is uniform again.
            const double u = static_cast<double>(2 * span + 1) / (2.0 * old.spans);
            for (int repeat = 0; repeat < old.multiplicity; ++repeat) midpoints.push_back(u);
        } else {
            midpoints.push_back(0.5 * (old.breaks[static_cast<size_t>(span)] + old.breaks[static_cast<size_t>(span) + 1]));
        }
    }
    std::vector<double> knots = old.knots;
    const Eigen::MatrixXd a = insertionMatrix(knots, old.degree, midpoints);
    return refineAxisBy(net, axis, a, std::move(knots), "refining along " + parameterAxisName(axis), out);
}

Status insertNetKnot(const LatticeNet& net, int axis, double at, int times, LatticeNet& out) {
    if (Status s = checkAxis(axis); !s) return s;
    const SplineAxis& old = net.axes[axis];
    const std::string where = "a knot at " + parameterAxisName(axis) + " = " + std::to_string(at);
    if (!(std::isfinite(at) && at > 0.0 && at < 1.0))
        return Status::error("cannot insert " + where + ": the parameter must lie strictly inside (0, 1) (the ends are clamped already)");
    if (times < 1 || times > old.degree)
        return Status::error("cannot insert " + where + " " + std::to_string(times) + " times: between 1 and the degree, " +
                             std::to_string(old.degree) + ", times");
    const double tau = old.knotParameter(at);
    const int present = static_cast<int>(std::count(old.knots.begin(), old.knots.end(), tau));
    if (present + times > old.degree)
        return Status::error("cannot insert " + where + " " + std::to_string(times) + " more time" + (times > 1 ? "s" : "") +
                             ": it is a knot of multiplicity " + std::to_string(present) + " already, and more than the degree (" +
                             std::to_string(old.degree) + ") would split the lattice apart there");
    std::vector<double> knots = old.knots;
    const Eigen::MatrixXd a = insertionMatrix(knots, old.degree, std::vector<double>(static_cast<size_t>(times), tau));
    return refineAxisBy(net, axis, a, std::move(knots), "inserting " + where, out);
}

Status removeNetSlice(const LatticeNet& net, int axis, int index, LatticeNet& out) {
    if (Status s = checkAxis(axis); !s) return s;
    const std::string along = " along " + parameterAxisName(axis);
    const int count = net.count[axis], degree = net.degree[axis], multiplicity = net.multiplicity[axis];
    if (index < 0 || index >= count)
        return Status::error("slice " + std::to_string(index) + along + " is out of range (the lattice has " + std::to_string(count) +
                             " slices" + along + ")");
    const std::string slice = "slice " + std::to_string(index) + along;
    if (count - 1 < degree + 1)
        return Status::error("cannot remove " + slice + ": the axis would keep " + std::to_string(count - 1) + " points, and degree " +
                             std::to_string(degree) + " needs at least " + std::to_string(degree + 1));
    const bool general = !net.knots[axis].empty();
    if (!general && !splineAxisCountValid(count - 1, degree, multiplicity))
        return Status::error("cannot remove " + slice + ": the axis repeats its interior knots " + std::to_string(multiplicity) +
                             " times, so its points come " + std::to_string(multiplicity) +
                             " per knot span and one slice alone cannot go (refine or rebuild the lattice instead)");
    if (net.periodic[axis] && (index == 0 || index == count - 1))
        return Status::error("cannot remove " + slice + ": it is the seam of the closed (periodic) axis, welded to slice " +
                             std::to_string(index == 0 ? count - 1 : 0) + "; removing it would open the lattice");
    for (int side = 0; side < 2; ++side)
        if (index == (side == 0 ? 0 : count - 1) && net.collapsedAlong[axis][side] != 0)
            return Status::error("cannot remove " + slice + ": it is a collapsed face (its points are welded into " +
                                 (net.collapsedAlong[axis][side] == ((7 & ~(1 << axis))) ? "one point" : "one line") +
                                 ", as a cylinder's axis or a ball's centre or pole); removing it would open a hole through the lattice");
    LatticeNet reduced;
    reduced.kind = net.kind;
    reduced.count = net.count;
    reduced.count[axis] = count - 1;
    reduced.degree = net.degree;
    reduced.multiplicity = net.multiplicity;
    reduced.knots = net.knots;
    if (general) {
        // A general knot vector loses the interior knot nearest the removed point's Greville abscissa (the
        // first of equals), so the axis keeps count + degree + 1 knots; a uniform axis is re-knotted uniformly.
        std::vector<double>& knots = reduced.knots[axis];
        const double xi = net.axes[axis].greville[static_cast<size_t>(index)];
        size_t drop = static_cast<size_t>(degree) + 1;
        for (size_t k = drop; k < static_cast<size_t>(count); ++k)
            if (std::abs(knots[k] - xi) < std::abs(knots[drop] - xi)) drop = k;
        knots.erase(knots.begin() + static_cast<std::ptrdiff_t>(drop));
    }
    const int n = reduced.slotCount();
    reduced.rest.resize(n, 3);
    reduced.weights.resize(n);
    std::vector<int> newId(net.slotCount(), -1);
    for (int s = 0; s < net.slotCount(); ++s) {
        std::array<int, 3> ijk = net.slotIjk(s);
        if (ijk[axis] == index) continue;
        if (ijk[axis] > index) --ijk[axis];
        const int t = reduced.slot(ijk[0], ijk[1], ijk[2]);
        newId[s] = t;
        reduced.rest.row(t) = net.rest.row(s);
        reduced.weights[static_cast<size_t>(t)] = net.weights[static_cast<size_t>(s)];
    }
    // Weld groups keep their remaining slots; new ids keep the old order, so the first survivor is the smallest.
    std::vector<int> groupRepresentative(net.slotCount(), -1);
    reduced.weldedTo.resize(n);
    for (int s = 0; s < net.slotCount(); ++s) {
        if (newId[s] < 0) continue;
        int& representative = groupRepresentative[net.weldedTo[s]];
        if (representative < 0) representative = newId[s];
        reduced.weldedTo[newId[s]] = representative;
    }
    return finishEdit(reduced, "removing " + slice, out);
}

Status applyNetEdits(const LatticeNet& net, const std::vector<NetEdit>& edits, LatticeNet& out) {
    LatticeNet current = net;
    for (size_t e = 0; e < edits.size(); ++e) {
        const NetEdit& edit = edits[e];
        LatticeNet next;
        Status s;
        switch (edit.kind) {
            case NetEdit::Kind::Move: s = moveNetPoints(current, edit.slots, edit.offset, next); break;
            case NetEdit::Kind::Merge: s = mergeNetPoints(current, edit.slots, next); break;
            case NetEdit::Kind::Refine: s = refineNetAxis(current, edit.axis, next); break;
            case NetEdit::Kind::Insert: s = insertNetKnot(current, edit.axis, edit.at, edit.times, next); break;
            case NetEdit::Kind::Remove: s = removeNetSlice(current, edit.axis, edit.index, next); break;
        }
        if (!s) return Status::error("edits[" + std::to_string(e) + "]: " + s.message);
        current = std::move(next);
    }
    out = std::move(current);
    return Status::success();
}

}  // namespace sculpt::core
