// Injectivity tests of the lattice deformation.
// J.E. Gain and N.A. Dodgson, "Preventing Self-Intersection under Free-Form Deformation", IEEE TVCG 7(4),
// 2001 (seed 003):
//   * Theorem 1 (section 5): injective if the deformation is C1 and det J > 0.
//   * Section 6: the exact test. det J of each cell as a Bezier (Bernstein) polynomial, recursively
//     subdivided by de Casteljau into octree boxes until every box has only positive coefficients (convex
//     hull: positive there) or a negative point is met. The paper needed >= 37 s for one cell; here det J
//     is multiplied out directly in Bernstein form per cell (injectivity_cell.cpp) in microseconds.
//   * Section 7 and the Appendix (InjectiveTest / FindDeviation): the conic-hull hodograph test.
//
// note: the conic test here works on the Bezier hodograph vectors of each cell rather than the B-spline
// control-point differences of the paper: every Bezier hodograph vector of a cell is a non-negative
// combination of the B-spline differences in its support, so its cones are never wider (a tighter,
// still sufficient test).
#include "core/injectivity/injectivity.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "core/spline/bernstein.h"
#include "core/injectivity/injectivity_cell.h"
#include "core/injectivity/injectivity_internal.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity_net.h"
#include "core/tspline/tspline_volume.h"

namespace sculpt::core {

namespace injectivity_detail {

std::vector<int> deformedCells(const Lattice& lattice, const std::vector<int>& requested, int& requestedCount) {
    const int cellCount = lattice.cellCount();
    requestedCount = requested.empty() ? cellCount : static_cast<int>(requested.size());
    std::vector<int> work;
    if (chunked(lattice)) {
        // The chunks whose support holds a moved control point (Volume::chunkSupport).
        std::vector<int> deformed = cellsInfluencedBy(lattice, displacedControlPoints(lattice));
        if (requested.empty()) return deformed;
        for (int cell : requested)
            if (std::binary_search(deformed.begin(), deformed.end(), cell)) work.push_back(cell);
        std::sort(work.begin(), work.end());
        work.erase(std::unique(work.begin(), work.end()), work.end());
        return work;
    }
    const int support = (lattice.degree[0] + 1) * (lattice.degree[1] + 1) * (lattice.degree[2] + 1);
    if (!requested.empty() && static_cast<long long>(requested.size()) * support < lattice.controlPointCount()) {
        // A few cells of a big lattice: look at their supports directly.
        for (int cell : requested) {
            assert(cell >= 0 && cell < cellCount);
            if (!cellIsUndeformed(lattice, cellIjk(lattice, cell))) work.push_back(cell);
        }
        std::sort(work.begin(), work.end());
        work.erase(std::unique(work.begin(), work.end()), work.end());
        return work;
    }
    // Otherwise mark the cells influenced by each moved control point: O(points + moved * support).
    std::vector<std::uint8_t> deformed(static_cast<size_t>(cellCount), 0);
    const std::array<int, 3> spans = lattice.spans();
    for (int idx = 0; idx < lattice.controlPointCount(); ++idx) {
        if (lattice.displacement(idx, 0) == 0.0 && lattice.displacement(idx, 1) == 0.0 &&
            lattice.displacement(idx, 2) == 0.0)
            continue;
        const std::array<int, 3> c = lattice.ijk(idx);
        int lo[3], hi[3];
        // Control point i is in the support of spans i-p .. i (box lattice); SplineAxis::supportSpans also
        // covers the repeated knots of net lattices.
        for (int a = 0; a < 3; ++a) lattice.axes[a].supportSpans(c[a], lo[a], hi[a]);
        for (int w = lo[2]; w <= hi[2]; ++w)
            for (int v = lo[1]; v <= hi[1]; ++v)
                for (int u = lo[0]; u <= hi[0]; ++u) deformed[u + spans[0] * (v + spans[1] * w)] = 1;
    }
    if (requested.empty()) {
        for (int cell = 0; cell < cellCount; ++cell)
            if (deformed[cell]) work.push_back(cell);
    } else {
        for (int cell : requested) {
            assert(cell >= 0 && cell < cellCount);
            if (deformed[cell]) {
                work.push_back(cell);
                deformed[cell] = 0;  // once
            }
        }
        std::sort(work.begin(), work.end());
    }
    return work;
}

}  // namespace injectivity_detail

using injectivity_detail::cellIjk;
using injectivity_detail::chunked;
using injectivity_detail::deformedCells;

namespace {

using Clock = std::chrono::steady_clock;

double elapsedMs(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

Eigen::Vector3d globalParams(const Lattice& lattice, const std::array<int, 3>& cell, const Eigen::Vector3d& local) {
    if (chunked(lattice)) return lattice.volume->chunkParameters(cell[0], local);
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) t[a] = (cell[a] + local[a]) / lattice.axes[a].spans;
    return t;
}


// note: a check of a few hundred cells is done on the calling thread, as the evaluation kernel does with
// small updates: waking the team costs more than it saves and, on a busy 2-core machine, can cost a
// scheduler quantum (~10 ms) while one worker waits to be scheduled. The estimates below are single-core
// microseconds measured here (cubic: ~0.55 us per cell for the conic test, ~13 us for the exact one).
constexpr double kParallelMicroseconds = 400.0;

double conicMicrosecondsPerCell(const Lattice& lattice) {
    const int n0 = lattice.degree[0] + 1, n1 = lattice.degree[1] + 1, n2 = lattice.degree[2] + 1;
    return 1.8e-4 * 3.0 * n0 * n1 * n2 * (n0 + n1 + n2 + 4);  // the Bezier passes plus the cones
}

double exactMicrosecondsPerCell(const Lattice& lattice) {
    const int p = lattice.degree[0], q = lattice.degree[1], r = lattice.degree[2];
    const double column = static_cast<double>(p) * (q + 1) * (r + 1);  // about the size of each J_a
    const double cross = (2.0 * p + 1) * (2 * q) * (2 * r);            // J_v x J_w
    return 2.6e-4 * (6.0 * column * column + 3.0 * column * cross);    // the products dominate
}

double exactMicrosecondsPerNetChunk(const Lattice& lattice) {
    const double p = lattice.degree[0], q = lattice.degree[1], r = lattice.degree[2];
    if (!lattice.rational) return exactMicrosecondsPerCell(lattice);
    // det4: 24 products of columns into 12 minors, then 6 products of minors (measured: ~25 us for a (2,2,2)
    // cylinder chunk, its turn count round the axis included).
    const double column = (p + 1) * (q + 1) * (r + 1);
    const double minor = (2 * p) * (2 * q) * (2 * r + 1);
    return 4.4e-4 * (24.0 * column * column + 6.0 * minor * minor);
}

void setFailingCell(const Lattice& lattice, int cell, const Eigen::Vector3d& local, InjectivityResult& result) {
    result.failingCell = cell;
    result.failingCellIjk = cellIjk(lattice, cell);
    result.failingLocalParams = local;
    result.failingParams = globalParams(lattice, result.failingCellIjk, local);
}

std::string formatPoint(const Eigen::Vector3d& t) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.4g, %.4g, %.4g)", t.x(), t.y(), t.z());
    return text;
}

std::string formatCell(const std::array<int, 3>& c) {
    return "(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + ")";
}

// ---- conic-hull hodograph test ------------------------------------------------------------------------

// note: the Appendix compares angles, theta_u + theta_v < pi/2 and then theta_x + theta_w < pi/2 with
// sin^2 theta_x = sin^2 theta_u + sin^2 theta_v (eq. 10). With s_a = sin^2 theta_a (all angles in
// [0, pi/2)) the second condition reads s_w < cos^2 theta_x = 1 - s_u - s_v, and it implies the first
// (s_v < 1 - s_u = cos^2 theta_u). So the whole test is s_u + s_v + s_w < 1, with s = (b^2 + c^2) / |P|^2
// for a hodograph vector P = (a, b, c) along its axis (FindDeviation's t = tan^2 theta = s / (1 - s)),
// after FindDeviation's rejection of a <= 0. No trigonometry, and nothing divides by a.
// Why eq. 10 bounds the cross product: for unit n = a x b / |a x b| and a at angle alpha <= theta_u from e_x,
// write a = cos(alpha) e_x + sin(alpha) a', a' a unit vector orthogonal to e_x; n . a = 0 gives
// |n_x| cos(alpha) = sin(alpha) |n . a'| <= sin(alpha) sqrt(1 - n_x^2), so n_x^2 <= sin^2 alpha; likewise
// n_y^2 <= sin^2 theta_v, hence sin^2 of the angle between n and e_z is n_x^2 + n_y^2 <= s_u + s_v < 1; n_z
// never vanishes on the (connected) cones and is +1 at a = e_x, b = e_y, so n stays near +e_z, and the
// angle between n and any c in the w cone is below theta_x + theta_w < pi/2: det[a b c] = n . c |a x b| > 0.
constexpr double kConicGuard = 1e-12;  // keeps rounding from certifying a sum that is 1 up to an ulp

enum class CellCheck { Certified, Failed, Unsupported };

CellCheck conicCell(const Lattice& lattice, const CellBezierBasis& basis, const std::array<int, 3>& cell,
                    double* bezier) {
    if (!cellIsPolynomial(lattice, cell)) return CellCheck::Unsupported;
    cellBezierDisplacement(lattice, basis, cell, bezier);
    std::array<double, 3> sinSquared{};
    const auto apart = [&] { return sinSquared[0] + sinSquared[1] + sinSquared[2] < 1.0 - kConicGuard; };
    if (cellHodographCones(basis, bezier, sinSquared) && apart()) return CellCheck::Certified;
    // Section 7's cones are around the rest axes; a cell the edit turned or scaled as a whole fails them at any
    // angle past ~45 degrees. In the frame of the cell's mean Jacobian it passes (point 3 of the certification
    // issue: rigid motions and scalings always pass).
    if (cellHodographConesInMeanFrame(basis, bezier, sinSquared) && apart()) return CellCheck::Certified;
    return CellCheck::Failed;
}

// ---- exact test ---------------------------------------------------------------------------------------

enum class BoxKind { Positive, Fold, Straddles };

struct Box {
    double lo[3];
    int depth = 0;
    size_t offset = 0;     // into the pool
    double minimum = 0.0;  // least coefficient (for the search order)
};

// capacity: the largest determinant polynomial searched (kMaxDeterminantCoefficients for box cells,
// kMaxNetDeterminantCoefficients for net chunks).
struct ExactWorkspace {
    std::vector<double> bezier, columnStorage, scratch, root;
    std::vector<double> halves, quarters, eighths;  // children of one octree split
    std::vector<double> pool;                       // coefficients of the boxes on the stack
    std::vector<Box> stack;
    explicit ExactWorkspace(int capacity = kMaxDeterminantCoefficients)
        : bezier(3 * kMaxCellControlPoints),
          columnStorage(9 * kMaxCellControlPoints),
          scratch(3 * kMaxDeterminantCoefficients),
          root(capacity),
          halves(2 * static_cast<size_t>(capacity)),
          quarters(4 * static_cast<size_t>(capacity)),
          eighths(8 * static_cast<size_t>(capacity)) {}
};

struct CellOutcome {
    // BrokenWeld: a net chunk's collapsed face whose welded points no longer coincide. Winding: det J > 0 in a
    // net chunk, but the lattice winds round its collapsed axis or pole other than once (value: the turns,
    // NaN if they could not be counted).
    enum Kind { Skipped, Positive, Fold, Undecided, Unsupported, NonFinite, BrokenWeld, Winding } kind = Skipped;
    Eigen::Vector3d local = Eigen::Vector3d::Constant(0.5);  // fold point, or least sampled point if undecided
    double value = 0.0;                                      // det J there
    double minSampled = std::numeric_limits<double>::infinity();
    Eigen::Vector3d minLocal = Eigen::Vector3d::Constant(0.5);  // where minSampled was seen
    double lowerBound = std::numeric_limits<double>::infinity();
    long long boxes = 0;
};

struct BoxSearch {
    const double* coefficients;
    BernsteinDegree degree;
    double foldThreshold;
    double certifyThreshold;
    CellOutcome* outcome;
};

// Corner coefficients are values of det J (a Bezier box interpolates its corners): a corner at or below the
// tolerance is a fold point. Otherwise all coefficients above the certify threshold prove the box
// positive (convex hull, section 6 step 4).
BoxKind examineBox(const BoxSearch& search, const double* c, const double lo[3], double size, double& minimum) {
    const BernsteinDegree& d = search.degree;
    CellOutcome& outcome = *search.outcome;
    ++outcome.boxes;
    for (int corner = 0; corner < 8; ++corner) {
        const int i = (corner & 1) ? d[0] : 0, j = (corner & 2) ? d[1] : 0, k = (corner & 4) ? d[2] : 0;
        const double value = c[i + (d[0] + 1) * (j + (d[1] + 1) * k)];
        if (value < outcome.minSampled) {
            outcome.minSampled = value;
            outcome.minLocal = Eigen::Vector3d(lo[0] + ((corner & 1) ? size : 0.0), lo[1] + ((corner & 2) ? size : 0.0),
                                               lo[2] + ((corner & 4) ? size : 0.0));
        }
        if (value <= search.foldThreshold) {
            outcome.kind = CellOutcome::Fold;
            outcome.local = Eigen::Vector3d(lo[0] + ((corner & 1) ? size : 0.0), lo[1] + ((corner & 2) ? size : 0.0),
                                            lo[2] + ((corner & 4) ? size : 0.0));
            outcome.value = value;
            return BoxKind::Fold;
        }
    }
    double maximum = 0.0;
    bernsteinCoefficientRange(c, d, minimum, maximum);
    if (minimum > search.certifyThreshold) {
        outcome.lowerBound = std::min(outcome.lowerBound, minimum);
        return BoxKind::Positive;
    }
    return BoxKind::Straddles;
}

// The least corner of a box that could not be decided, for the Undecided report.
void noteUndecided(const BoxSearch& search, const double* c, const double lo[3], double size) {
    const BernsteinDegree& d = search.degree;
    CellOutcome& outcome = *search.outcome;
    for (int corner = 0; corner < 8; ++corner) {
        const int i = (corner & 1) ? d[0] : 0, j = (corner & 2) ? d[1] : 0, k = (corner & 4) ? d[2] : 0;
        const double value = c[i + (d[0] + 1) * (j + (d[1] + 1) * k)];
        if (outcome.kind != CellOutcome::Undecided || value < outcome.value) {
            outcome.kind = CellOutcome::Undecided;
            outcome.value = value;
            outcome.local = Eigen::Vector3d(lo[0] + ((corner & 1) ? size : 0.0), lo[1] + ((corner & 2) ? size : 0.0),
                                            lo[2] + ((corner & 4) ? size : 0.0));
        }
    }
}

// Depth-first octree search of one cell's det J (section 6, step 4). Children are split off along u, then
// v, then w (de Casteljau at 1/2) and the most negative-looking child is searched first, so a fold shows up
// early; the search stops at the first fold point.
void searchCell(const BoxSearch& search, const ExactOptions& options, ExactWorkspace& work) {
    CellOutcome& outcome = *search.outcome;
    const BernsteinDegree& d = search.degree;
    const size_t n = static_cast<size_t>(bernsteinCoefficientCount(d));
    const double rootLo[3] = {0.0, 0.0, 0.0};
    double rootMinimum = 0.0;
    const BoxKind rootKind = examineBox(search, search.coefficients, rootLo, 1.0, rootMinimum);
    if (rootKind == BoxKind::Fold) return;
    if (rootKind == BoxKind::Positive) {
        outcome.kind = CellOutcome::Positive;
        return;
    }
    if (options.maxSubdivisionDepth <= 0) {
        noteUndecided(search, search.coefficients, rootLo, 1.0);
        return;
    }
    work.stack.clear();
    if (work.pool.size() < n) work.pool.resize(n);
    std::copy(search.coefficients, search.coefficients + n, work.pool.begin());
    work.stack.push_back(Box{{0.0, 0.0, 0.0}, 0, 0, rootMinimum});
    bool undecided = false;
    while (!work.stack.empty()) {
        const Box parent = work.stack.back();
        work.stack.pop_back();
        if (outcome.boxes >= options.maxBoxesPerCell) {
            noteUndecided(search, work.pool.data() + parent.offset, parent.lo, std::ldexp(1.0, -parent.depth));
            undecided = true;
            continue;  // drain the stack: every box left is undecided
        }
        // Split into 8 children: u halves, then v, then w.
        const double* source = work.pool.data() + parent.offset;
        splitBernstein(source, d, 0, 0.5, work.halves.data(), work.halves.data() + n);
        for (int h = 0; h < 2; ++h)
            splitBernstein(work.halves.data() + h * n, d, 1, 0.5, work.quarters.data() + (2 * h) * n,
                           work.quarters.data() + (2 * h + 1) * n);
        for (int q = 0; q < 4; ++q)
            splitBernstein(work.quarters.data() + q * n, d, 2, 0.5, work.eighths.data() + (2 * q) * n,
                           work.eighths.data() + (2 * q + 1) * n);
        const double childSize = std::ldexp(1.0, -(parent.depth + 1));
        // Child index 2q + e with q = 2h + g: halves along u (h), v (g), w (e).
        Box pending[8];
        int pendingCount = 0;
        for (int child = 0; child < 8; ++child) {
            const int h = child >> 2, g = (child >> 1) & 1, e = child & 1;
            Box box;
            box.lo[0] = parent.lo[0] + h * childSize;
            box.lo[1] = parent.lo[1] + g * childSize;
            box.lo[2] = parent.lo[2] + e * childSize;
            box.depth = parent.depth + 1;
            const double* c = work.eighths.data() + child * n;
            const BoxKind kind = examineBox(search, c, box.lo, childSize, box.minimum);
            if (kind == BoxKind::Fold) return;
            if (kind == BoxKind::Positive) continue;
            if (box.depth >= options.maxSubdivisionDepth) {
                noteUndecided(search, c, box.lo, childSize);
                undecided = true;
                continue;
            }
            box.offset = static_cast<size_t>(child);  // temporarily: which eighth
            pending[pendingCount++] = box;
        }
        // Push the straddling children, most negative last (searched first). The parent's slot is free now.
        for (int p = 1; p < pendingCount; ++p)  // insertion sort, descending minimum (at most 8 boxes)
            for (int q = p; q > 0 && pending[q - 1].minimum < pending[q].minimum; --q)
                std::swap(pending[q - 1], pending[q]);
        size_t top = parent.offset;
        if (work.pool.size() < top + pendingCount * n) work.pool.resize(top + pendingCount * n);
        for (int p = 0; p < pendingCount; ++p) {
            const double* c = work.eighths.data() + pending[p].offset * n;
            std::copy(c, c + n, work.pool.begin() + static_cast<std::ptrdiff_t>(top));
            pending[p].offset = top;
            work.stack.push_back(pending[p]);
            top += n;
        }
    }
    if (undecided && outcome.kind != CellOutcome::Fold) outcome.kind = CellOutcome::Undecided;
    if (!undecided) outcome.kind = CellOutcome::Positive;
}

void exactCell(const Lattice& lattice, const CellBezierBasis& basis, const std::array<int, 3>& cell,
               const ExactOptions& options, ExactWorkspace& work, CellOutcome& outcome) {
    if (!cellIsPolynomial(lattice, cell)) {
        outcome.kind = CellOutcome::Unsupported;
        return;
    }
    const int countPerColumn = 3 * kMaxCellControlPoints;
    double* columns[3] = {work.columnStorage.data(), work.columnStorage.data() + countPerColumn,
                          work.columnStorage.data() + 2 * countPerColumn};
    cellBezierDisplacement(lattice, basis, cell, work.bezier.data());
    cellJacobianColumns(basis, work.bezier.data(), columns);
    // Bound on the terms of det J = J_u . (J_v x J_w): each Bernstein product coefficient is a convex
    // combination of products of factor coefficients, so every one of the 6 terms is at most
    // max|J_u| max|J_v| max|J_w|. The rounding guard is relative to that.
    double termBound = 6.0;
    for (int a = 0; a < 3; ++a) {
        const int count = 3 * bernsteinCoefficientCount(columnDegree(basis, a));
        double largest = 0.0;
        for (int i = 0; i < count; ++i) largest = std::max(largest, std::abs(columns[a][i]));
        termBound *= largest;
    }
    cellDeterminantBernstein(basis, columns, work.scratch.data(), work.root.data());
    // A non-finite displacement would make every box straddle until the work limit: refuse it outright.
    const int coefficientCount = bernsteinCoefficientCount(determinantDegree(basis));
    for (int c = 0; c < coefficientCount; ++c)
        if (!std::isfinite(work.root[c])) {
            outcome.kind = CellOutcome::NonFinite;
            outcome.value = std::numeric_limits<double>::quiet_NaN();
            return;
        }
    BoxSearch search{work.root.data(), determinantDegree(basis), options.tolerance,
                     options.tolerance + options.roundingGuard * termBound, &outcome};
    searchCell(search, options, work);
}

ExactWorkspace& exactWorkspace() {
    // note: one per OpenMP worker, kept between calls so the per-drag check allocates nothing after the first.
    thread_local ExactWorkspace workspace;
    return workspace;
}

// A net lattice's chunk (injectivity_net.h): the sign polynomial of det(dQ/dt), divided by the collapsed
// faces' factors, searched like a box cell's det J. With a tolerance, det J > tolerance is
// det(dQ/dt) - tolerance det(dQ0/dt) > 0: the same polynomial form of the rest volume (same factors W^4 and
// face powers) is subtracted, so the searched polynomial is positive iff det J > tolerance.
struct NetExactWorkspace {
    ExactWorkspace search{kMaxNetDeterminantCoefficients};
    NetChunkWorkspace chunk;
    std::vector<double> rest = std::vector<double>(kMaxNetDeterminantCoefficients);
};

NetExactWorkspace& netExactWorkspace() {
    thread_local NetExactWorkspace workspace;
    return workspace;
}

void exactNetChunk(const Lattice& lattice, int chunk, double weldTolerance, const ExactOptions& options, NetExactWorkspace& work,
                   CellOutcome& outcome) {
    if (options.tolerance == 0.0 && lattice.volume->weldGroupList().empty()) {
        // A cubic chunk without welds or collapsed faces (a weighted T-spline's Bezier element): first the Jacobian
        // hull of its homogeneous points in the frame of dQ/dt at each box centre (proveChunkJacobian,
        // tspline_rest.cpp). Its guard is relative to each box's own terms, where the Bernstein form of
        // W^4 det dQ/dt below is guarded relative to the largest terms over the chunk, which with weights varying
        // 100:1 or more exceed det itself: such chunks were never decided (measured: 35-124 s a drag on a 26k-vertex
        // scan at depth 4, refused). What the hull leaves undecided goes on to the Bernstein search.
        const ChunkJacobianProof proof = proveChunkJacobian(*lattice.volume, chunk, &lattice.displacement);
        if (proof.kind != ChunkJacobianProof::NotApplicable) outcome.boxes += std::max(1LL, proof.boxes);
        if (proof.kind == ChunkJacobianProof::Proven) {
            outcome.kind = CellOutcome::Positive;
            outcome.lowerBound = 0.0;
            outcome.minLocal = Eigen::Vector3d::Constant(0.5);
            outcome.minSampled = chunkJacobianDeterminant(lattice, chunk, outcome.minLocal);
            return;
        }
        if (proof.kind == ChunkJacobianProof::Fold) {
            // det dQ/dt <= 0 evaluated there, and det dQ0/dt > 0 (the rest is proven): det J <= 0.
            outcome.kind = CellOutcome::Fold;
            outcome.local = proof.local;
            outcome.value = chunkJacobianDeterminant(lattice, chunk, proof.local);
            outcome.minSampled = outcome.value;
            outcome.minLocal = proof.local;
            return;
        }
    }
    NetChunkDeterminantInfo info;
    double* root = work.search.root.data();
    chunkDeterminantBernstein(lattice, chunk, weldTolerance, true, work.chunk, root, info);
    const int coefficientCount = bernsteinCoefficientCount(info.degree);
    for (int c = 0; c < coefficientCount; ++c)
        if (!std::isfinite(root[c])) {
            outcome.kind = CellOutcome::NonFinite;
            outcome.value = std::numeric_limits<double>::quiet_NaN();
            return;
        }
    if (!info.weldsHold) {
        outcome.kind = CellOutcome::BrokenWeld;
        return;
    }
    double certifyThreshold = options.roundingGuard * info.termBound;
    if (options.tolerance != 0.0) {
        NetChunkDeterminantInfo restInfo;
        chunkDeterminantBernstein(lattice, chunk, weldTolerance, false, work.chunk, work.rest.data(), restInfo);
        if (!restInfo.weldsHold || restInfo.degree != info.degree) {
            outcome.kind = CellOutcome::BrokenWeld;
            return;
        }
        for (int c = 0; c < coefficientCount; ++c) root[c] -= options.tolerance * work.rest[c];
        certifyThreshold += options.roundingGuard * std::abs(options.tolerance) * restInfo.termBound;
    }
    BoxSearch search{root, info.degree, 0.0, certifyThreshold, &outcome};
    searchCell(search, options, work.search);
    // The search saw values of a polynomial with the sign of det J - tolerance; report det J itself. The least
    // sampled point is moved 1e-3 off a collapsed face (det J is continuous there; its limit costs two more
    // chunk polynomials), the fold or undecided point is evaluated where it is.
    if (outcome.kind == CellOutcome::Positive || outcome.kind == CellOutcome::Undecided) {
        Eigen::Vector3d at = outcome.minLocal;
        for (int a = 0; a < 3; ++a) {
            if (info.divided[a][0] > 0) at[a] = std::max(at[a], 1e-3);
            if (info.divided[a][1] > 0) at[a] = std::min(at[a], 1.0 - 1e-3);
        }
        outcome.minSampled = chunkJacobianDeterminant(lattice, chunk, at);
    }
    if (outcome.kind == CellOutcome::Positive) outcome.lowerBound = options.tolerance;
    if (outcome.kind == CellOutcome::Fold || outcome.kind == CellOutcome::Undecided)
        outcome.value = chunkJacobianDeterminant(lattice, chunk, outcome.local);
    // A positive quotient on a face collapsed along one axis still allows a ring wound twice round it
    // (injectivity_net.h): count the turns, once per face.
    for (int a = 0; a < 3 && outcome.kind == CellOutcome::Positive; ++a)
        for (int side = 0; side < 2; ++side) {
            if (info.divided[a][side] != 1) continue;
            double turns = std::numeric_limits<double>::quiet_NaN();
            bool closed = false;
            const bool counted = chunkRingWinding(lattice, chunk, a, side, weldTolerance, work.chunk, turns, closed);
            const bool once = closed ? std::abs(std::round(turns)) == 1.0 : std::abs(turns) < 1.0;
            if (counted && once) continue;
            outcome.kind = CellOutcome::Winding;
            outcome.value = counted ? turns : std::numeric_limits<double>::quiet_NaN();
            outcome.local = Eigen::Vector3d::Constant(0.5);
            outcome.local[a] = side;
            break;
        }
}

}  // namespace

const char* injectivityModeName(InjectivityMode mode) {
    switch (mode) {
        case InjectivityMode::Off: return "off";
        case InjectivityMode::Conic: return "conic";
        case InjectivityMode::Exact: return "exact";
    }
    return "?";
}

bool parseInjectivityMode(const std::string& name, InjectivityMode& mode) {
    for (InjectivityMode m : {InjectivityMode::Off, InjectivityMode::Conic, InjectivityMode::Exact})
        if (name == injectivityModeName(m)) {
            mode = m;
            return true;
        }
    return false;
}

const char* injectivityVerdictName(InjectivityVerdict verdict) {
    switch (verdict) {
        case InjectivityVerdict::Certified: return "certified";
        case InjectivityVerdict::NotCertified: return "not certified";
        case InjectivityVerdict::Fold: return "fold";
        case InjectivityVerdict::Undecided: return "undecided";
        case InjectivityVerdict::Unsupported: return "unsupported";
    }
    return "?";
}

namespace {

// The common start of both tests: which of the requested cells are deformed (the only ones that can fail),
// with the counts and the boundary flag filled into the result.
std::vector<int> cellsToCheck(const Lattice& lattice, const std::vector<int>& cells, InjectivityResult& result) {
    std::vector<int> work = deformedCells(lattice, cells, result.cellsChecked);
    result.cellsDeformed = static_cast<int>(work.size());
    result.boundaryFixed = boundaryUnmoved(lattice);
    return work;
}

// Lowers `first` to w if w is smaller: the lowest-index failure is reported whatever the thread timing.
void noteFirst(std::atomic<int>& first, int w) {
    int current = first.load();
    while (w < current && !first.compare_exchange_weak(current, w)) {
    }
}

// The exact test's per-cell loop over a box lattice's deformed cells; returns the first folding one (count if none).
int exactBoxCells(const Lattice& lattice, const ExactOptions& options, const std::vector<int>& work,
                  std::vector<CellOutcome>& outcomes) {
    const int count = static_cast<int>(work.size());
    std::atomic<int> firstFold{count};
    const CellBezierBasis basis = makeCellBezierBasis(lattice);
    const bool parallel = count > 1 && count * exactMicrosecondsPerCell(lattice) > kParallelMicroseconds;
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (int w = 0; w < count; ++w) {
        // Skip cells after a known fold; the lowest-index fold is always found (deterministic report).
        if (w > firstFold.load(std::memory_order_relaxed)) continue;
        exactCell(lattice, basis, cellIjk(lattice, work[w]), options, exactWorkspace(), outcomes[w]);
        if (outcomes[w].kind == CellOutcome::Fold) noteFirst(firstFold, w);
    }
    return firstFold.load();
}

// The same over a net lattice's deformed chunks.
int exactNetChunks(const Lattice& lattice, const ExactOptions& options, const std::vector<int>& work,
                   std::vector<CellOutcome>& outcomes) {
    const int count = static_cast<int>(work.size());
    std::atomic<int> firstFold{count};
    // Welded points coincide to 1e-9 of the rest diagonal (finishLatticeNet's rule).
    const double weldTolerance = 1e-9 * lattice.volume->restBounds().diagonal().norm();
    const bool parallel = count > 1 && count * exactMicrosecondsPerNetChunk(lattice) > kParallelMicroseconds;
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (int w = 0; w < count; ++w) {
        if (w > firstFold.load(std::memory_order_relaxed)) continue;
        exactNetChunk(lattice, work[w], weldTolerance, options, netExactWorkspace(), outcomes[w]);
        if (outcomes[w].kind == CellOutcome::Fold) noteFirst(firstFold, w);
    }
    return firstFold.load();
}

std::string formatValue(double value) {
    char text[48];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

}  // namespace

InjectivityResult checkInjectivityConic(const Lattice& lattice, const std::vector<int>& cells) {
    if (lattice.boxTurned()) return checkInjectivityConic(unturnedLattice(lattice), cells);  // the same det J (lattice.h)
    if (lattice.volume) {
        // note: the cones of section 7 are around the axes e_a, the directions of a box lattice's hodographs at
        // rest; a curved net's rest hodographs point anywhere, so the cones would fail at rest. The exact test
        // decides net chunks instead (a few times slower, and never weaker).
        InjectivityResult result = checkInjectivityExact(lattice, ExactOptions{}, cells);
        if (!result.message.empty()) result.message += " (net lattice: the conic test runs the exact test)";
        return result;
    }
    const Clock::time_point start = Clock::now();
    InjectivityResult result;
    const std::vector<int> work = cellsToCheck(lattice, cells, result);
    const int count = result.cellsDeformed;
    std::vector<CellCheck> checks(static_cast<size_t>(count), CellCheck::Certified);
    std::atomic<int> firstFailure{count};
    if (count > 0) {
        const CellBezierBasis basis = makeCellBezierBasis(lattice);
        const bool parallel = count * conicMicrosecondsPerCell(lattice) > kParallelMicroseconds;
#pragma omp parallel if (parallel)
        {
            double bezier[3 * kMaxCellControlPoints];
#pragma omp for schedule(dynamic, 16)
            for (int w = 0; w < count; ++w) {
                // Section 7, step 3: halt at the first failing cell. Cells after a known failure are skipped;
                // the lowest failing one is always examined, so the report does not depend on timing.
                if (w > firstFailure.load(std::memory_order_relaxed)) continue;
                checks[w] = conicCell(lattice, basis, cellIjk(lattice, work[w]), bezier);
                if (checks[w] != CellCheck::Certified) noteFirst(firstFailure, w);
            }
        }
    }
    const int failing = firstFailure.load();
    if (failing == count) {
        result.certified = true;
        result.verdict = InjectivityVerdict::Certified;
    } else {
        setFailingCell(lattice, work[failing], Eigen::Vector3d::Constant(0.5), result);
        if (checks[failing] == CellCheck::Unsupported) {
            result.verdict = InjectivityVerdict::Unsupported;
            result.message = "cell " + formatCell(result.failingCellIjk) +
                             " has differing NURBS weights; the conic test covers polynomial cells only, so the "
                             "deformation is not certified";
        } else {
            result.verdict = InjectivityVerdict::NotCertified;
            result.message = "conic test: the hodograph cones of cell " + formatCell(result.failingCellIjk) +
                             " overlap, so injectivity is not certified there (the deformation may still be injective)";
        }
    }
    result.milliseconds = elapsedMs(start);
    return result;
}

InjectivityResult checkInjectivityExact(const Lattice& lattice, const ExactOptions& options,
                                        const std::vector<int>& cells) {
    if (lattice.boxTurned()) return checkInjectivityExact(unturnedLattice(lattice), options, cells);  // the same det J (lattice.h)
    const Clock::time_point start = Clock::now();
    InjectivityResult result;
    const std::vector<int> work = cellsToCheck(lattice, cells, result);
    const int count = result.cellsDeformed;
    std::vector<CellOutcome> outcomes(static_cast<size_t>(count));
    const bool net = lattice.volume != nullptr;
    int fold = count;
    if (count > 0) fold = net ? exactNetChunks(lattice, options, work, outcomes) : exactBoxCells(lattice, options, work, outcomes);
    const char* unit = net ? "chunk " : "cell ";
    // Combine in cell order: a fold anywhere decides; otherwise the first undecided / unsupported cell.
    const bool undeformedChecked = result.cellsChecked > count;
    double minSampled = undeformedChecked ? 1.0 : std::numeric_limits<double>::infinity();
    double lowerBound = undeformedChecked ? 1.0 : std::numeric_limits<double>::infinity();
    int firstOpen = -1;
    for (int w = 0; w < count; ++w) {
        const CellOutcome& o = outcomes[w];
        result.boxesExamined += o.boxes;
        if (o.kind == CellOutcome::Skipped) continue;
        minSampled = std::min(minSampled, o.minSampled);
        lowerBound = std::min(lowerBound, o.lowerBound);
        if ((o.kind == CellOutcome::Undecided || o.kind == CellOutcome::Unsupported || o.kind == CellOutcome::NonFinite ||
             o.kind == CellOutcome::BrokenWeld || o.kind == CellOutcome::Winding) &&
            firstOpen < 0)
            firstOpen = w;
    }
    if (fold < count) {
        const CellOutcome& o = outcomes[fold];
        setFailingCell(lattice, work[fold], o.local, result);
        result.verdict = InjectivityVerdict::Fold;
        result.minDeterminantFound = o.value;
        result.message = "exact test: det J = " + formatValue(o.value) + " at lattice parameters " +
                         formatPoint(result.failingParams) + " in " + unit + formatCell(result.failingCellIjk) +
                         (o.value < 0.0 ? ": the deformation folds there (not injective)"
                                        : ": not above the tolerance there (degenerate or nearly so; not certified)");
    } else if (firstOpen >= 0) {
        const CellOutcome& o = outcomes[firstOpen];
        setFailingCell(lattice, work[firstOpen], o.local, result);
        result.minDeterminantFound = minSampled;
        if (o.kind == CellOutcome::Unsupported || o.kind == CellOutcome::NonFinite || o.kind == CellOutcome::BrokenWeld) {
            result.verdict = o.kind == CellOutcome::Unsupported ? InjectivityVerdict::Unsupported : InjectivityVerdict::Undecided;
            result.failingLocalParams = Eigen::Vector3d::Constant(0.5);
            result.failingParams = globalParams(lattice, result.failingCellIjk, result.failingLocalParams);
            if (o.kind == CellOutcome::Unsupported)
                result.message = "cell " + formatCell(result.failingCellIjk) +
                                 " has differing NURBS weights; the exact test covers polynomial cells only, so the "
                                 "deformation is not certified";
            else if (o.kind == CellOutcome::NonFinite)
                result.message = "exact test: " + std::string(unit) + formatCell(result.failingCellIjk) +
                                 " has non-finite control point displacements; not certified";
            else
                result.message = "exact test: chunk " + formatCell(result.failingCellIjk) +
                                 " lies on a collapsed face (an axis or a pole) whose welded control points no longer "
                                 "coincide; not certified";
        } else if (o.kind == CellOutcome::Winding) {
            result.verdict = InjectivityVerdict::Undecided;
            result.message = "exact test: det J > 0 in chunk " + formatCell(result.failingCellIjk) + ", but near " +
                             formatPoint(result.failingParams) + " the lattice " +
                             (std::isnan(o.value) ? std::string("turns round its collapsed axis (or pole) in a way that could not be counted")
                                                  : "turns " + formatValue(o.value) + " times round its collapsed axis (or pole), so it is "
                                                    "not one to one there") +
                             "; not certified";
        } else {
            result.verdict = InjectivityVerdict::Undecided;
            result.message = "exact test: undecided in " + std::string(unit) + formatCell(result.failingCellIjk) +
                             " after the subdivision limit (det J sampled down to " + formatValue(o.value) + " near " +
                             formatPoint(result.failingParams) + "); not certified";
        }
    } else {
        result.certified = true;
        result.verdict = InjectivityVerdict::Certified;
        result.minDeterminantFound = minSampled;
        result.determinantLowerBound = lowerBound;
    }
    result.milliseconds = elapsedMs(start);
    return result;
}

InjectivityResult checkInjectivity(const Lattice& lattice, InjectivityMode mode) {
    return checkInjectivity(lattice, mode, {});
}

InjectivityResult checkInjectivity(const Lattice& lattice, InjectivityMode mode, const std::vector<int>& cells) {
    switch (mode) {
        case InjectivityMode::Off: {
            InjectivityResult result;
            result.certified = true;
            result.verdict = InjectivityVerdict::Certified;
            return result;
        }
        case InjectivityMode::Conic: return checkInjectivityConic(lattice, cells);
        case InjectivityMode::Exact: return checkInjectivityExact(lattice, ExactOptions{}, cells);
    }
    return {};
}

}  // namespace sculpt::core
