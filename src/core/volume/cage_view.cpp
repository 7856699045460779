// The cage as drawn (cage_view.h): Coquillart 1990, 3.1.2 (welded points act as one control point, so they
// are drawn and picked once) and 3.4 (the frozen lattice's volume is what deforms the surface, so its
// curved chunk edges are what the user sees of it).
#include "core/volume/cage_view.h"

namespace sculpt::core {

Positions carryThroughLayers(const std::vector<Layer>& layers, const Positions& points) {
    Positions out = points;
    if (layers.empty()) return out;
    for (Eigen::Index p = 0; p < out.rows(); ++p) {
        Eigen::Vector3d x = out.row(p).transpose();
        // note: the same map as LatticeStack::pushThroughLayers, which cagePoints() uses, so curves and points agree.
        for (const Layer& layer : layers) x = layerImage(layer.lattice, x);
        out.row(p) = x.transpose();
    }
    return out;
}

CageView cageView(const Session& session, int samplesPerSpan) {
    CageView view;
    const Lattice& lattice = session.lattice();
    view.points = session.cage().cagePoints();
    const int count = lattice.controlPointCount();
    view.representative.assign(static_cast<size_t>(count), 1);
    if (!lattice.volume) return view;
    for (int id = 0; id < count; ++id) view.representative[static_cast<size_t>(id)] = lattice.representative(id) == id;
    view.edges = controlNetEdges(lattice);
    view.curves = chunkEdgeCurves(lattice, samplesPerSpan);
    for (Positions& curve : view.curves) curve = carryThroughLayers(session.cage().layers(), curve);
    return view;
}

std::vector<Positions> restChunkEdges(const std::shared_ptr<const Volume>& volume, int samplesPerSpan) {
    if (!volume) return {};
    LatticeSettings settings;
    settings.volume = volume;  // shared, not copied: makeLatticeInBox only reads it (no freezing, no mesh)
    Lattice lattice;
    if (!makeLatticeInBox(settings, volume->restBounds().min(), volume->restBounds().max(), lattice)) return {};
    return chunkEdgeCurves(lattice, samplesPerSpan);
}

}  // namespace sculpt::core
