// The directional bound of det J for cells displaced along one line (injectivity.h).
#include <algorithm>
#include <cmath>

#include "core/spline/bernstein.h"
#include "core/injectivity/injectivity.h"
#include "core/injectivity/injectivity_cell.h"

namespace sculpt::core {

std::vector<int> cellsLeftByDirectionalBound(const Lattice& lattice, const std::vector<int>& cells) {
    if (lattice.boxTurned()) return cellsLeftByDirectionalBound(unturnedLattice(lattice), cells);  // the same det J (lattice.h)
    if (lattice.volume || lattice.rational) return cells;
    for (int a = 0; a < 3; ++a)
        if (!lattice.axes[a].uniform()) return cells;
    const std::array<int, 3> spans = lattice.spans();
    const std::array<int, 3> p = lattice.degree;
    // The derivative of the displacement's component w along box axis a, at any point, is a convex combination of
    // the divided differences p (w_i - w_{i-1}) / (t_{i+p} - t_i) along a of the coefficients whose functions are
    // non-zero there (de Boor: the derivative's B-spline coefficients, weighted by the basis functions of the
    // other axes too). For a displacement along a box axis (a brush layer: its pull, or one lateral axis of its
    // widening) det J = 1 + dw/dx_a, so the least divided difference over the lattice, per unit of the box's
    // extent, bounds it from below everywhere: where that proves every cell, no cell need be looked at.
    // divided(a, c): the divided difference ending at control point c along a (c's index along a >= 1).
    const auto divided = [&](int a, const std::array<int, 3>& c) {
        std::array<int, 3> b = c;
        --b[a];
        const std::vector<double>& t = lattice.axes[a].knots;
        const double width = t[static_cast<size_t>(c[a] + p[a])] - t[static_cast<size_t>(c[a])];
        const double difference = lattice.displacement(lattice.index(c[0], c[1], c[2]), a) - lattice.displacement(lattice.index(b[0], b[1], b[2]), a);
        return p[a] * difference / (width * (lattice.boxMax[a] - lattice.boxMin[a]));
    };
    {
        const Eigen::Vector3d largest = lattice.displacement.cwiseAbs().colwise().maxCoeff().transpose();
        int axis = -1;
        largest.maxCoeff(&axis);
        bool alongOneAxis = largest[axis] > 0.0;
        for (int a = 0; a < 3; ++a) alongOneAxis = alongOneAxis && (a == axis || largest[a] <= 1e-12 * largest[axis]);
        if (alongOneAxis) {
            double least = INFINITY;
            std::array<int, 3> from{0, 0, 0};  // every control point but the first along the axis ends a difference
            from[static_cast<size_t>(axis)] = 1;
            for (int k = from[2]; k < lattice.count[2]; ++k)
                for (int j = from[1]; j < lattice.count[1]; ++j)
                    for (int i = from[0]; i < lattice.count[0]; ++i) least = std::min(least, divided(axis, {i, j, k}));
            if (1.0 + least > 1e-9) return {};
        }
    }
    const int n = (p[0] + 1) * (p[1] + 1) * (p[2] + 1);
    std::vector<int> left;
    std::vector<double> s(static_cast<size_t>(n));
    std::vector<int> ids(static_cast<size_t>(n));
    const CellBezierBasis basis = makeCellBezierBasis(lattice);
    std::vector<double> bezier(3 * static_cast<size_t>(n)), along(static_cast<size_t>(n)), raised(static_cast<size_t>(n)),
        sum(static_cast<size_t>(n));
    std::array<std::vector<double>, 3> columns;
    for (auto& c : columns) c.resize(3 * static_cast<size_t>(n));
    for (int cell : cells) {
        const int su = cell % spans[0], sv = (cell / spans[0]) % spans[1], sw = cell / (spans[0] * spans[1]);
        const std::array<int, 3> first{lattice.axes[0].first(su), lattice.axes[1].first(sv), lattice.axes[2].first(sw)};
        // The support's displacements: the largest one gives the direction e.
        double largest = 0.0;
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        int l = 0;
        for (int k = 0; k <= p[2]; ++k)
            for (int j = 0; j <= p[1]; ++j)
                for (int i = 0; i <= p[0]; ++i, ++l) {
                    const int id = lattice.index(first[0] + i, first[1] + j, first[2] + k);
                    ids[static_cast<size_t>(l)] = id;
                    const double norm = lattice.displacement.row(id).norm();
                    if (norm > largest) {
                        largest = norm;
                        e = lattice.displacement.row(id).transpose() / norm;
                    }
                }
        if (largest == 0.0) continue;  // undeformed: det J = 1
        bool parallel = true;
        for (int c = 0; c < n && parallel; ++c) {
            const Eigen::Vector3d d = lattice.displacement.row(ids[static_cast<size_t>(c)]).transpose();
            s[static_cast<size_t>(c)] = d.dot(e);
            parallel = (d - s[static_cast<size_t>(c)] * e).norm() <= 1e-12 * largest;
        }
        if (!parallel) {
            left.push_back(cell);
            continue;
        }
        // Along a box axis: the least divided difference of the cell's support (above) bounds det J; where it
        // proves the cell, the Bernstein form below is not needed.
        int boxAxis = -1;
        for (int a = 0; a < 3; ++a)
            if (std::abs(e[a]) >= 1.0 - 1e-12) boxAxis = a;
        if (boxAxis >= 0) {
            const int a = boxAxis;
            double least = INFINITY;
            for (int k = 0; k <= p[2]; ++k)
                for (int j = 0; j <= p[1]; ++j)
                    for (int i = 0; i <= p[0]; ++i) {
                        const std::array<int, 3> q{i, j, k};
                        if (q[a] > 0) least = std::min(least, divided(a, {first[0] + i, first[1] + j, first[2] + k}));
                    }
            if (1.0 + least > 1e-9) continue;
        }
        // det J = 1 + e . grad s = sum_a e_a (e . J_a), J_a the Jacobian's columns; each e . J_a in Bernstein form
        // over the cell, raised to the cell's degree along a, so the sum's coefficients bound det J from below.
        const std::array<int, 3> ijk{su, sv, sw};
        cellBezierDisplacement(lattice, basis, ijk, bezier.data());
        double* const column[3] = {columns[0].data(), columns[1].data(), columns[2].data()};
        cellJacobianColumns(basis, bezier.data(), column);
        std::fill(sum.begin(), sum.begin() + n, 0.0);
        for (int a = 0; a < 3; ++a) {
            if (e[a] == 0.0) continue;
            const BernsteinDegree cd = columnDegree(basis, a);
            const int count = bernsteinCoefficientCount(cd);
            for (int c = 0; c < count; ++c)
                along[static_cast<size_t>(c)] = e[0] * columns[a][static_cast<size_t>(c)] + e[1] * columns[a][static_cast<size_t>(count + c)] +
                                                e[2] * columns[a][static_cast<size_t>(2 * count + c)];
            elevateBernstein(along.data(), cd, a, raised.data());
            for (int c = 0; c < n; ++c) sum[static_cast<size_t>(c)] += e[a] * raised[static_cast<size_t>(c)];
        }
        const double bound = *std::min_element(sum.begin(), sum.begin() + n);
        if (!(bound > 1e-9)) left.push_back(cell);
    }
    return left;
}

}  // namespace sculpt::core
