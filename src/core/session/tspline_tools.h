// TSplineTools: the weighted T-spline volume's tools (Song & Yang 2005, "Free-form deformation with weighted
// T-spline", seed 002): setting one up around the mesh, subdividing its cells, and sculpting by its weights.
// One per Session (Session::tspline()). Set-up and subdivision are made of the lattice-tool commands
// (tool_library.h), so undo, redo and recordings treat them as any other tool change or freeze; a weight tool
// is one history operation of its own. Files: tspline_tools.cpp (set-up, subdivision), tspline_weights.cpp
// (the weight tools and their steps).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/session/operation.h"
#include "core/status.h"

namespace sculpt::core {

class Session;

class TSplineTools {
public:
    // A handle on `session` (Session::tspline()), made per call; the tools keep no state of their own.
    explicit TSplineTools(Session& session) : s_(session) {}

    // Sec. 4 / sec. 6 steps 1-3: the octree T-spline volume of the current mesh's vertices inside the region
    // (makeOctreeTSplineVolumeInBox: cells holding a vertex subdivided down to the depth, 2:1-balanced, weights
    // ratio : 1), added as a lattice tool (ToolLibrary::add) and, with setup.freeze, frozen (ToolLibrary::freeze,
    // no pin layers): two history operations, each undone on its own; recordings write the tool explicitly.
    // Errors (depth or root out of range, weight ratio not finite and > 0, an empty or non-finite region, a
    // region holding no vertex, a drag in progress) use the script's field names and change nothing.
    Status setup(const TSplineSetup& setup, OpReport& report);
    // Sec. 6 step 2 / Fig. 11: local octree subdivision of T-spline tool `index` (not frozen) as an edit of the
    // tool (ToolLibrary::edit: a history operation, recorded with the resulting tool). The cells: the ids in
    // `cells` plus the leaf cells holding the world points `at` (the rest volume's parameters of each point,
    // as picking gives them); then the 2:1 balance if `balance`. The control points are placed again at the
    // Greville points of the finer lattice and the weights are set again from the mesh as in setup
    // (subdivideTSplineVolume). Refused, changing nothing: a frozen tool, a tool that is not a T-spline, a cell
    // id out of range, a point outside the tool, no cell at all, points moved one by one.
    Status subdivideCells(int index, const std::vector<int>& cells, const std::vector<Eigen::Vector3d>& at, bool balance,
                          OpReport& report);

    // Sculpting by weights (sec. 1 and 6; weight_sculpt.h). One history operation on the frozen weighted
    // T-spline; the mesh is Q(P; W)(t) at its frozen parameters (eq. 5), so a weight change moves it. Heights are
    // measured along the bump direction n from the rest surface under the current weights
    // (Session::mesh().rest), i.e. H_v = n . (x_v - X0_v) = n . sum R_s(t_v) delta_s.
    //  * SetWeights: the weights of `ids` become `weights`.
    //  * Hammer: the bump of the control points S (WeightToolSettings) at the picked vertex p is
    //    b(t) = sum_{s in S} R_s(t) delta_s and n = b(t_p) / |b(t_p)|. The displacements of S are scaled by one
    //    factor so that H_p becomes `height` (or H_p + (scale - 1) n.b(t_p)): b's shape is kept exactly. With
    //    no bump yet (b(t_p) = 0), n is the vertex normal and every point of S moves by the same mu n.
    //  * Crimp: the weights of S are multiplied by one factor beta and their displacements scaled by lambda(beta)
    //    so that H_p stays; beta is found (bisection on log beta) so that the equivalent diameter 2 sqrt(A / pi)
    //    of the rest surface where H >= H_p / 2 (linear within triangles) is widthFactor times what it was.
    // Checked like a control-point move (injectivity of the cells reached, the rest volume under the new
    // weights, no new triangle crossing); a change that fails is Rejected and changes nothing. Errors (change
    // nothing): no frozen T-spline, ids, vertex or control point out of range, a hidden control point, a
    // weight or factor not finite and > 0, a crimp without a bump, a width that no weight reaches.
    Status sculptWeights(const WeightToolSettings& settings, OpReport& report);
    // The control points a sculpting tool acts on, its bump direction n and the heights H_v of the vertices in
    // their support (as sculptWeights computes them), for the window and tests. Errors as sculptWeights.
    struct Bump {
        std::vector<int> controlPoints;
        Eigen::Vector3d direction = Eigen::Vector3d::Zero();
        std::vector<int> vertices;
        std::vector<double> heights;
        double width = 0.0;  // the equivalent diameter at half the picked vertex's height (0 without a bump)
    };
    Status bumpAt(const WeightToolSettings& settings, Bump& out) const;
    // Control points of the frozen T-spline's non-empty cells (nonEmptyTSplineCells of the rest positions, less
    // the boundary copies): the ones shown and picked (Fig. 10; tspline_view.h); empty when the frozen lattice
    // is not a T-spline.
    std::vector<int> visiblePoints() const;

private:
    friend class Session;

    // The bump of sculptWeights' tools: the control points, direction, sums and heights.
    Status weightBump(const WeightToolSettings& settings, WeightBump& out) const;
    Status applyTool(const WeightToolSettings& settings, Step step, const std::string& label, OpReport& report);
    // A recorded weight change fits the frozen lattice: a T-spline, ids in range, `before` its weights bitwise.
    Status checkRecordedWeights(const WeightChange& change) const;
    // Applies a step's weight change and control displacement to the frozen T-spline, the rest mesh (rebased so
    // it stays Q0(t) under the new weights) and the output, recording in step.weightUndo what it overwrote.
    Status applyStep(const Step& step, std::vector<int>* moved);
    void revertStep(const Step& step, std::vector<int>* moved);

    Session& s_;
};

}  // namespace sculpt::core
