#include "app/scene_builder.h"

#include <algorithm>

#include "core/injectivity.h"

namespace sculpt::app {

render::SceneData sceneFromSession(const core::Session& session, const SceneRequest& request) {
    render::SceneData scene;
    if (request.mesh) {
        scene.positions = session.positions();
        scene.triangles = session.triangles();
    }
    const core::Lattice& lattice = session.lattice();
    scene.lattice.nu = lattice.count[0];
    scene.lattice.nv = lattice.count[1];
    scene.lattice.nw = lattice.count[2];
    scene.lattice.controlPoints = core::controlPointPositions(lattice);
    scene.lattice.pinned = lattice.pinned;
    scene.lattice.selected = request.selectedControlPoints;

    const core::Operation* last = session.historyCursor() > 0 ? &session.history()[session.historyCursor() - 1] : nullptr;
    if (request.lastDragConstraints && last && last->kind == core::OperationKind::Drag) {
        const auto& constraints = last->interactive ? last->steps.back().constraints : last->constraints;
        scene.constraints.sources.resize(static_cast<Eigen::Index>(constraints.size()), 3);
        scene.constraints.targets.resize(static_cast<Eigen::Index>(constraints.size()), 3);
        for (size_t c = 0; c < constraints.size(); ++c) {
            scene.constraints.sources.row(static_cast<Eigen::Index>(c)) = constraints[c].source.transpose();
            scene.constraints.targets.row(static_cast<Eigen::Index>(c)) = constraints[c].target.transpose();
        }
    }
    if (request.jacobian) {
        const std::vector<double> det = session.totalJacobianDeterminants();
        scene.jacobianDet.assign(det.begin(), det.end());
    }
    if (request.affected) {
        std::vector<int> ids = request.affectedControlPoints;
        if (ids.empty() && last && !last->steps.empty()) ids = last->steps.back().delta.indices;
        core::controlPointInfluence(lattice, session.embedding(), ids, scene.affectedWeight);
    }
    return scene;
}

}  // namespace sculpt::app
