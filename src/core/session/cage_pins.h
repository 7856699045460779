// CagePins: which of the cage's control points may move (Session::pins()). A pinned point keeps its place in
// every drag and edit (Hu et al. 2001 solve only for the free points). Pins come from three places: the pin
// layers of the lattice's settings, the boundary a net lattice that does not hold the whole mesh keeps (Gain &
// Dodgson 2001, section 5; Coquillart 1990, 3.4), and the user's pins and unpins, which are relative to the
// other two. A welded point (one point in several chunks) pins as one. Pins are no operation on the shape:
// each change is journaled, and each operation keeps the pins it was applied with (Operation::pinToggles) so
// recordings replay it the same way. A handle made per call over the session's cage; files: cage_pins.cpp.
#pragma once

#include <vector>

#include "core/status.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"

namespace sculpt::core {

class Session;

class CagePins {
public:
    explicit CagePins(Session& session) : s_(session) {}

    // Pins or unpins control points (ids as Lattice::index, with their weld groups). An id outside the lattice:
    // an error, nothing changes.
    Status set(const std::vector<int>& indices, bool pinned);
    // The control points whose pin differs from the settings' pin layers and the partial boundary (the user's
    // pins and unpins), sorted.
    std::vector<int> toggles() const;
    // Pins exactly the settings' pin layers and the partial boundary, with the listed control points flipped.
    // Bad ids or a drag in progress change nothing.
    Status setToggles(const std::vector<int>& toggled);

private:
    friend class Session;

    // A net lattice that does not hold every vertex keeps its boundary faces pinned: the vertices outside it
    // never move, so a moving boundary would tear the mesh there and the deformation of space (identity
    // outside, the volume inside) would not be injective (Gain & Dodgson 2001, section 5: the boundary
    // condition; Coquillart 1990, 3.4 keeps the outer planes fixed for the same seam). Not with the injectivity
    // test off (a plain FFD, Session::setInjectivity).
    void pinBoundaryIfPartial(Lattice& lattice, const Embedding& embedding) const;
    // True for a control point that only pinBoundaryIfPartial pins (not a pin layer): the reason a move of it is
    // refused says so, and how to lift it.
    bool pinnedAsPartialBoundary(int idx) const;
    // The pin a control point has before the user's pin edits: the pin layers, and the partial boundary.
    bool basePinned(int idx) const;
    // The ids with every slot of their weld groups added (sorted, unique).
    std::vector<int> weldGroupsOf(const std::vector<int>& ids) const;
    // Journals the pins as they are now (consecutive changes: only where they ended counts).
    void journal();

    Session& s_;
};

}  // namespace sculpt::core
