// What the window and the screenshots draw of the cage and of the lattice tools, and what the lattice tool
// picks (Coquillart 1990, EFFD, 3.1-3.4): a lattice of any shape is shown by its control net (each weld group
// once, on its representative) and by the curved chunk edges of its volume, both as the user sees them,
// i.e. carried through the layers applied after the cage (session.h), like Session::cagePoints().
// Plain data, no GL: the renderer's LatticeView is filled from it in the app.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/volume/lattice.h"
#include "core/mesh_types.h"
#include "core/session/session.h"

namespace sculpt::core {

struct CageView {
    Positions points;  // #P x 3: the cage's control points as shown (Session::cagePoints(), rows by Lattice::index)
    // 1 per control point that is drawn and picked: every point of the box lattice; of a net lattice only the
    // representative of each weld group (Lattice::representative), so a welded axis or seam is one marker.
    std::vector<std::uint8_t> representative;
    // Net lattice only (empty for the box lattice, which the renderer draws as its grid):
    std::vector<std::array<int, 2>> edges;  // controlNetEdges: pairs of representative ids
    std::vector<Positions> curves;          // chunkEdgeCurves, carried through the layers; each #samples x 3
};

// The cage of `session` as drawn, chunk edges sampled `samplesPerSpan` (>= 1) segments per knot span.
// Costs #curve samples x (1 + #layers) lattice evaluations (a 2 x 12 x 2 cylinder at 8: about 600).
CageView cageView(const Session& session, int samplesPerSpan);

// Points carried through `layers` in order (x -> x + sum R(t(x)) delta, the identity outside a layer's box):
// where a point of the cage's image is shown. points #N x 3; returns #N x 3.
Positions carryThroughLayers(const std::vector<Layer>& layers, const Positions& points);

// A lattice tool at rest, as drawn where it is not frozen: its chunk edges (chunkEdgeCurves of the
// undeformed net), `samplesPerSpan` segments per knot span. Empty for a null net.
std::vector<Positions> restChunkEdges(const std::shared_ptr<const Volume>& volume, int samplesPerSpan);

}  // namespace sculpt::core
