// CagePins: the cage's pins (the boundary a partial lattice keeps, the pin layers, the user's pins, weld
// groups), journaled so recordings replay them.
#include "core/session/cage_pins.h"

#include "core/session/session.h"
#include "core/session/session_internal.h"

#include <algorithm>

namespace sculpt::core {


void CagePins::pinBoundaryIfPartial(Lattice& lattice, const Embedding& embedding) const {
    // A volume that is not one tensor product (a composite) keeps its outer surface always: the boundary
    // overlap test (lattice_boundary.h) tessellates tensor lattices only. A plain FFD (no test) pins nothing.
    const bool chunked = lattice.volume && !lattice.tensorNet();
    if (s_.injectivity_.mode == InjectivityMode::Off) return;
    if (!lattice.volume || (!chunked && embedding.insideCount() == static_cast<int>(s_.mesh_.positions.rows()))) return;
    for (int idx = 0; idx < lattice.controlPointCount(); ++idx)
        if (lattice.volume->onOuterSurface(idx)) lattice.pinned[idx] = 1;
}

bool CagePins::basePinned(int idx) const {
    if (inOuterLayers(s_.stack_.lattice_, idx, s_.stack_.settings_.pinLayers)) return true;
    return pinnedAsPartialBoundary(idx);
}

bool CagePins::pinnedAsPartialBoundary(int idx) const {
    return s_.injectivity_.mode != InjectivityMode::Off && s_.stack_.lattice_.volume && s_.stack_.lattice_.volume->onOuterSurface(idx) &&
           (!s_.stack_.lattice_.tensorNet() || s_.stack_.embedding_.insideCount() < static_cast<int>(s_.mesh_.positions.rows()));
}

std::vector<int> CagePins::weldGroupsOf(const std::vector<int>& ids) const {
    std::vector<int> out;
    for (int idx : ids) {
        const std::vector<int>* group = s_.stack_.lattice_.volume ? weldGroupOf(*s_.stack_.lattice_.volume, idx) : nullptr;
        if (group)
            out.insert(out.end(), group->begin(), group->end());
        else
            out.push_back(idx);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::vector<int> CagePins::toggles() const {
    std::vector<int> toggled;
    for (int idx = 0; idx < s_.stack_.lattice_.controlPointCount(); ++idx)
        if (basePinned(idx) != static_cast<bool>(s_.stack_.lattice_.pinned[idx])) toggled.push_back(idx);
    return toggled;
}

Status CagePins::setToggles(const std::vector<int>& toggled) {
    const int n = s_.stack_.lattice_.controlPointCount();
    for (int idx : toggled)
        if (idx < 0 || idx >= n) return Status::error("control point id " + std::to_string(idx) + " is outside the lattice");
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    for (int idx = 0; idx < n; ++idx) s_.stack_.lattice_.pinned[idx] = basePinned(idx) ? 1 : 0;
    // A welded point is one control point: a toggle of any of its slots toggles the group once.
    for (int idx : weldGroupsOf(toggled)) s_.stack_.lattice_.pinned[idx] ^= 1;
    pinBoundaryIfPartial(s_.stack_.lattice_, s_.stack_.embedding_);
    journal();
    return Status::success();
}

Status CagePins::set(const std::vector<int>& indices, bool pinned) {
    const int n = s_.stack_.lattice_.controlPointCount();
    for (int idx : indices)
        if (idx < 0 || idx >= n) return Status::error("control point id " + std::to_string(idx) + " is outside the lattice");
    for (int idx : weldGroupsOf(indices)) s_.stack_.lattice_.pinned[idx] = pinned ? 1 : 0;
    pinBoundaryIfPartial(s_.stack_.lattice_, s_.stack_.embedding_);
    journal();
    return Status::success();
}

void CagePins::journal() {
    // Consecutive pin changes: only where they ended counts.
    s_.history_.note(JournalEntry{JournalEntry::Kind::Pins, {}, 0, {}, toggles(), s_.stack_.settings_}, true);
}

}  // namespace sculpt::core
