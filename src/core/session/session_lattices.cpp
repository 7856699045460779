// Lattices of any shape in the session (Coquillart 1990, EFFD): the list of lattice tools associated with the
// mesh, freezing one (3.3) and unfreezing it, each a history operation.
#include "core/session/session.h"
#include "core/session/session_internal.h"

#include <algorithm>

namespace sculpt::core {

namespace {

Status checkTool(const LatticeTool& tool) {
    if (!tool.volume) return Status::error("the lattice tool has no lattice");
    if (tool.name.empty()) return Status::error("the lattice tool needs a name");
    return Status::success();
}

}  // namespace

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
    if (inOuterLayers(lattice_, idx, settings_.pinLayers)) return true;
    return pinnedAsPartialBoundary(idx);
}

bool Session::pinnedAsPartialBoundary(int idx) const {
    return injectivity_.mode != InjectivityMode::Off && lattice_.volume && lattice_.volume->onOuterSurface(idx) &&
           (!lattice_.tensorNet() || embedding_.insideCount() < static_cast<int>(positions_.rows()));
}

void Session::setInjectivity(const InjectivitySettings& settings) {
    const bool testing = injectivity_.mode != InjectivityMode::Off;
    injectivity_ = settings;
    if (!testing && settings.mode != InjectivityMode::Off && !drag_.active && lattice_.controlPointCount() > 0)
        pinBoundaryIfPartial(lattice_, embedding_);
}

std::vector<int> Session::weldGroupsOf(const std::vector<int>& ids) const {
    std::vector<int> out;
    for (int idx : ids) {
        const std::vector<int>* group = lattice_.volume ? weldGroupOf(*lattice_.volume, idx) : nullptr;
        if (group)
            out.insert(out.end(), group->begin(), group->end());
        else
            out.push_back(idx);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void Session::applyToolChange(const Operation& operation, bool forward) {
    const LatticeTool& from = forward ? operation.toolBefore : operation.toolAfter;
    const LatticeTool& to = forward ? operation.toolAfter : operation.toolBefore;
    const auto at = tools_.begin() + operation.toolIndex;
    if (!from.volume) tools_.insert(at, to);       // added (forward) or a removal taken back
    else if (!to.volume) tools_.erase(at);         // removed (forward) or an addition taken back
    else tools_[static_cast<size_t>(operation.toolIndex)] = to;
}

Status Session::pushToolChange(Operation operation, OpReport& report) {
    applyToolChange(operation, true);
    frozenTool_ = operation.frozenAfter;
    pushOperation(std::move(operation));
    lastMoved_.clear();
    lastMovedAll_ = false;
    report.status = OpStatus::Applied;
    return Status::success();
}

Status Session::addLatticeTool(const LatticeTool& tool, OpReport& report) {
    report = OpReport{};
    report.op = "add_lattice";
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (Status s = checkTool(tool); !s) return s;
    Operation operation;
    operation.kind = OperationKind::LatticeTools;
    operation.label = "add lattice " + tool.name;
    operation.toolIndex = static_cast<int>(tools_.size());
    operation.toolAfter = tool;
    operation.frozenBefore = operation.frozenAfter = frozenTool_;
    return pushToolChange(std::move(operation), report);
}

Status Session::editLatticeTool(int index, const LatticeTool& tool, OpReport& report) {
    report = OpReport{};
    report.op = "edit_lattice";
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (index < 0 || index >= static_cast<int>(tools_.size())) return Status::error("there is no lattice " + std::to_string(index));
    if (index == frozenTool_)
        return Status::error("lattice " + tools_[static_cast<size_t>(index)].name + " is frozen: unfreeze it before editing its shape");
    if (Status s = checkTool(tool); !s) return s;
    Operation operation;
    operation.kind = OperationKind::LatticeTools;
    operation.label = "edit lattice " + tool.name;
    operation.toolIndex = index;
    operation.toolBefore = tools_[static_cast<size_t>(index)];
    operation.toolAfter = tool;
    operation.frozenBefore = operation.frozenAfter = frozenTool_;
    return pushToolChange(std::move(operation), report);
}

Status Session::removeLatticeTool(int index, OpReport& report) {
    report = OpReport{};
    report.op = "remove_lattice";
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (index < 0 || index >= static_cast<int>(tools_.size())) return Status::error("there is no lattice " + std::to_string(index));
    if (index == frozenTool_) return Status::error("lattice " + tools_[static_cast<size_t>(index)].name + " is frozen: unfreeze it first");
    Operation operation;
    operation.kind = OperationKind::LatticeTools;
    operation.label = "remove lattice " + tools_[static_cast<size_t>(index)].name;
    operation.toolIndex = index;
    operation.toolBefore = tools_[static_cast<size_t>(index)];
    operation.frozenBefore = frozenTool_;
    operation.frozenAfter = frozenTool_ > index ? frozenTool_ - 1 : frozenTool_;
    return pushToolChange(std::move(operation), report);
}

Status Session::freezeLattice(int index, int pinLayers, OpReport& report) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (index < 0 || index >= static_cast<int>(tools_.size())) return Status::error("there is no lattice " + std::to_string(index));
    LatticeSettings settings;
    settings.volume = tools_[static_cast<size_t>(index)].volume;
    settings.pinLayers = pinLayers;
    if (Status s = validateLatticeSettings(settings); !s) return s;
    // Freezing a lattice that holds no vertex would do nothing but replace the cage: say so instead.
    {
        const Volume& volume = *settings.volume;
        const Eigen::AlignedBox3d box = volume.restBounds();
        bool holds = false;
        for (Eigen::Index v = 0; v < positions_.rows() && !holds; ++v) {
            const Eigen::Vector3d x = positions_.row(v).transpose();
            Eigen::Vector3d t;
            holds = box.contains(x) && volume.freeze(x, t);
        }
        if (!holds)
            return Status::error("lattice " + tools_[static_cast<size_t>(index)].name +
                                 " holds none of the mesh's vertices: place it over the part to deform (Place on mesh in the Lattices panel, \"place\" in scripts)");
    }
    const int before = frozenTool_;
    if (Status s = setupLattice(settings, report); !s) return s;
    report.op = "freeze";
    if (report.status != OpStatus::Applied) return Status::success();
    frozenTool_ = index;
    Operation& operation = history_.last();
    operation.label = "freeze lattice " + tools_[static_cast<size_t>(index)].name;
    operation.frozenBefore = before;
    operation.frozenAfter = index;
    history_.lastJournaled().label = operation.label;
    history_.lastJournaled().frozenBefore = before;
    history_.lastJournaled().frozenAfter = index;
    int inside = embedding_.insideCount();
    report.reason = "froze " + std::to_string(inside) + " of " + std::to_string(positions_.rows()) + " vertices in lattice " +
                    tools_[static_cast<size_t>(index)].name;
    return Status::success();
}

Status Session::unfreezeLattice(OpReport& report) {
    if (frozenTool_ < 0) {
        report = OpReport{};
        report.op = "unfreeze";
        report.status = OpStatus::NoOp;
        report.reason = "no lattice is frozen";
        return Status::success();
    }
    const int before = frozenTool_;
    LatticeSettings box = initialSettings_;
    box.hasRegion = false;  // around the mesh as it is now
    if (Status s = setupLattice(box, report); !s) return s;
    report.op = "unfreeze";
    if (report.status != OpStatus::Applied) return Status::success();
    frozenTool_ = -1;
    Operation& operation = history_.last();
    operation.label = "unfreeze lattice " + tools_[static_cast<size_t>(before)].name;
    operation.frozenBefore = before;
    operation.frozenAfter = -1;
    history_.lastJournaled().label = operation.label;
    history_.lastJournaled().frozenBefore = before;
    history_.lastJournaled().frozenAfter = -1;
    return Status::success();
}

}  // namespace sculpt::core
