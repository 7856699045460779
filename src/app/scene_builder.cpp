#include "app/scene_builder.h"

#include <algorithm>
#include <utility>

#include "core/volume/cage_view.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/tspline/tspline_view.h"

namespace sculpt::app {

render::SceneData sceneFromSession(const core::Session& session, const SceneRequest& request) {
    render::SceneData scene;
    if (request.mesh) {
        scene.positions = session.mesh().positions;
        scene.triangles = session.mesh().triangles;
    }
    const core::Lattice& lattice = session.lattice();
    scene.lattice.nu = lattice.count[0];
    scene.lattice.nv = lattice.count[1];
    scene.lattice.nw = lattice.count[2];
    const core::TSplineVolume* tspline = core::asTSpline(lattice.volume.get());
    // A T-spline is drawn by its T-lattice at its control points (Fig. 9-10), not by curves: at depth 4 the
    // curved cell edges of a pot were a cloud that hid it.
    core::CageView cage = tspline ? core::CageView{session.cage().cagePoints(), {}, {}, {}} : core::cageView(session, request.curveSamplesPerSpan);
    scene.lattice.controlPoints = std::move(cage.points);  // the cage as shown: carried through the layers
    scene.lattice.pinned = lattice.pinned;
    scene.lattice.selected = request.selectedControlPoints;
    if (lattice.volume) {
        scene.lattice.netEdges = std::move(cage.edges);
        scene.lattice.curves = std::move(cage.curves);
        scene.lattice.drawn = std::move(cage.representative);  // welded points once
    }
    if (tspline) {
        const core::TSplineBasis& basis = tspline->basis();
        // Fig. 10: the light control points serve the parametrization only and stay hidden; the T-lattice shows.
        scene.lattice.drawn = request.drawnControlPoints.empty() ? core::tsplineCageView(session).controlPoints : request.drawnControlPoints;
        scene.lattice.netEdges = core::tlatticeNetEdges(basis);
        scene.lattice.edgesOfHiddenPoints = true;
        const std::vector<int> junctions = core::tJunctionVertices(basis.lattice);
        scene.lattice.tJunctions.resize(static_cast<Eigen::Index>(junctions.size()), 3);
        for (size_t j = 0; j < junctions.size(); ++j)
            scene.lattice.tJunctions.row(static_cast<Eigen::Index>(j)) = scene.lattice.controlPoints.row(core::vertexAnchor(basis, junctions[j]));
    }
    if (lattice.volume && request.drawnControlPoints.size() == scene.lattice.drawn.size()) scene.lattice.drawn = request.drawnControlPoints;
    if (request.latticeTools) {
        const std::vector<core::LatticeTool>& tools = session.tools().list();
        for (size_t t = 0; t < tools.size(); ++t) {
            if (static_cast<int>(t) == session.tools().frozen()) continue;  // drawn as the cage
            std::vector<Positions> curves = restToolLines(tools[t].volume, request.curveSamplesPerSpan);
            for (Positions& curve : curves) scene.lattice.toolCurves.push_back(std::move(curve));
        }
    }

    const core::Operation* last = session.history().cursor() > 0 ? &session.history()[session.history().cursor() - 1] : nullptr;
    if (request.lastDragConstraints && last && last->kind == core::OperationKind::Drag) {
        const auto& constraints = last->interactive ? last->steps.back().constraints : last->constraints;
        scene.constraints.sources.resize(static_cast<Eigen::Index>(constraints.size()), 3);
        scene.constraints.targets.resize(static_cast<Eigen::Index>(constraints.size()), 3);
        // A scripted drag records its pulls as asked (BrushSettings::askedTarget); the strength took the surface
        // that share of the way. An interactive one's last step holds where the points got.
        const bool scaled = !last->interactive && last->brush.strength != 1.0;
        for (size_t c = 0; c < constraints.size(); ++c) {
            const Eigen::Vector3d& source = constraints[c].source;
            const Eigen::Vector3d target = scaled ? last->brush.scaledTarget(source, constraints[c].target) : constraints[c].target;
            scene.constraints.sources.row(static_cast<Eigen::Index>(c)) = source.transpose();
            scene.constraints.targets.row(static_cast<Eigen::Index>(c)) = target.transpose();
        }
    }
    if (request.jacobian) {
        const std::vector<double> det = session.totalJacobianDeterminants();
        scene.jacobianDet.assign(det.begin(), det.end());
    }
    if (request.affected) {
        std::vector<int> ids = request.affectedControlPoints;
        // The last operation's last step: in the cage, or in the layer it made (a brush region or a
        // subdivision step; the newest layer, since later operations were undone).
        const bool stroke = ids.empty() && last && !last->steps.empty() && last->steps.back().region;
        const bool inLayer = ids.empty() && last && !last->steps.empty() && last->steps.back().freshFrame && !session.cage().layers().empty();
        if (ids.empty() && last && !last->steps.empty()) ids = last->steps.back().delta.indices;
        if (stroke) {
            // A brush stroke: its regions (one per grabbed image), placed again from their steps, since a finished
            // stroke is baked into the rest shape and its layers are gone; the strongest influence of any of them.
            scene.affectedWeight.assign(static_cast<size_t>(session.mesh().positions.rows()), 0.0f);
            for (const core::Step& step : last->steps) {
                if (!step.region) continue;
                core::Lattice region;
                if (!core::makeLatticeInBox(step.settings, step.frameMin, step.frameMax, region) || !core::turnBoxLattice(region, step.frameAxes))
                    continue;
                std::vector<float> weight;
                core::controlPointInfluence(region, core::embedVertices(region, session.mesh().positions), step.delta.indices, weight);
                for (size_t v = 0; v < weight.size() && v < scene.affectedWeight.size(); ++v)
                    scene.affectedWeight[v] = std::max(scene.affectedWeight[v], weight[v]);
            }
        } else if (inLayer) {
            // note: the layer's input is the mesh before its step; the mesh now is near enough for a tint.
            const core::Lattice& layer = session.cage().layers().back().lattice;
            core::controlPointInfluence(layer, core::embedVertices(layer, session.mesh().positions), ids, scene.affectedWeight);
        } else {
            core::controlPointInfluence(lattice, session.cage().embedding(), ids, scene.affectedWeight);
        }
    }
    return scene;
}

std::vector<float> sessionVertexColors(const io::ObjMesh& source, const core::Session& session) {
    const io::VertexColors colours = io::meshVertexColours(source, session.refinement().appliedSplits());
    if (colours.rows() != session.mesh().positions.rows()) return {};
    std::vector<float> rgb(3 * static_cast<size_t>(colours.rows()));
    for (Eigen::Index v = 0; v < colours.rows(); ++v)
        for (int c = 0; c < 3; ++c) rgb[3 * static_cast<size_t>(v) + static_cast<size_t>(c)] = colours(v, c);
    return rgb;
}

std::vector<Positions> restToolLines(const std::shared_ptr<const core::Volume>& volume, int samplesPerSpan) {
    const core::TSplineVolume* tspline = core::asTSpline(volume.get());
    if (!tspline) return core::restChunkEdges(volume, samplesPerSpan);
    std::vector<Positions> lines;
    const Positions& rest = tspline->restControlPoints();
    for (const std::array<int, 2>& edge : core::tlatticeNetEdges(tspline->basis())) {
        Positions segment(2, 3);
        segment.row(0) = rest.row(edge[0]);
        segment.row(1) = rest.row(edge[1]);
        lines.push_back(std::move(segment));
    }
    return lines;
}

}  // namespace sculpt::app
