// Session: the cage's pins (the boundary a partial lattice keeps, the user's pins, weld groups) and the
// injectivity setting.
#include "core/session/session.h"
#include "core/session/session_internal.h"

#include <algorithm>

namespace sculpt::core {


void Session::pinBoundaryIfPartial(Lattice& lattice, const Embedding& embedding) const {
    // A volume that is not one tensor product (a composite) keeps its outer surface always: the boundary
    // overlap test (lattice_boundary.h) tessellates tensor lattices only. A plain FFD (no test) pins nothing.
    const bool chunked = lattice.volume && !lattice.tensorNet();
    if (injectivity_.mode == InjectivityMode::Off) return;
    if (!lattice.volume || (!chunked && embedding.insideCount() == static_cast<int>(positions_.rows()))) return;
    for (int idx = 0; idx < lattice.controlPointCount(); ++idx)
        if (lattice.volume->onOuterSurface(idx)) lattice.pinned[idx] = 1;
}

bool Session::basePinned(int idx) const {
    if (inOuterLayers(stack_.lattice_, idx, stack_.settings_.pinLayers)) return true;
    return pinnedAsPartialBoundary(idx);
}

bool Session::pinnedAsPartialBoundary(int idx) const {
    return injectivity_.mode != InjectivityMode::Off && stack_.lattice_.volume && stack_.lattice_.volume->onOuterSurface(idx) &&
           (!stack_.lattice_.tensorNet() || stack_.embedding_.insideCount() < static_cast<int>(positions_.rows()));
}

void Session::setInjectivity(const InjectivitySettings& settings) {
    const bool testing = injectivity_.mode != InjectivityMode::Off;
    injectivity_ = settings;
    if (!testing && settings.mode != InjectivityMode::Off && !drag_.active && stack_.lattice_.controlPointCount() > 0)
        pinBoundaryIfPartial(stack_.lattice_, stack_.embedding_);
}

std::vector<int> Session::weldGroupsOf(const std::vector<int>& ids) const {
    std::vector<int> out;
    for (int idx : ids) {
        const std::vector<int>* group = stack_.lattice_.volume ? weldGroupOf(*stack_.lattice_.volume, idx) : nullptr;
        if (group)
            out.insert(out.end(), group->begin(), group->end());
        else
            out.push_back(idx);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace sculpt::core
