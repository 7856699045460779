// ToolLibrary: lattices of any shape in the session (Coquillart 1990, EFFD): the list of lattice tools associated
// with the mesh, freezing one (3.3) and unfreezing it, each a history operation.
#include "core/session/tool_library.h"

#include "core/session/session.h"
#include "core/session/session_internal.h"

namespace sculpt::core {

namespace {

Status checkTool(const LatticeTool& tool) {
    if (!tool.volume) return Status::error("the lattice tool has no lattice");
    if (tool.name.empty()) return Status::error("the lattice tool needs a name");
    return Status::success();
}

}  // namespace

const std::vector<LatticeTool>& ToolLibrary::list() const { return s_.tools_.list; }

int ToolLibrary::frozen() const { return s_.tools_.frozen; }

void ToolLibrary::applyChange(const Operation& operation, bool forward) {
    const LatticeTool& from = forward ? operation.toolBefore : operation.toolAfter;
    const LatticeTool& to = forward ? operation.toolAfter : operation.toolBefore;
    const auto at = s_.tools_.list.begin() + operation.toolIndex;
    if (!from.volume) s_.tools_.list.insert(at, to);       // added (forward) or a removal taken back
    else if (!to.volume) s_.tools_.list.erase(at);         // removed (forward) or an addition taken back
    else s_.tools_.list[static_cast<size_t>(operation.toolIndex)] = to;
}

Status ToolLibrary::pushChange(Operation operation, OpReport& report) {
    applyChange(operation, true);
    s_.tools_.frozen = operation.frozenAfter;
    s_.pushOperation(std::move(operation));
    s_.lastMoved_.vertices.clear();
    s_.lastMoved_.all = false;
    report.status = OpStatus::Applied;
    return Status::success();
}

Status ToolLibrary::add(const LatticeTool& tool, OpReport& report) {
    report = OpReport{};
    report.op = "add_lattice";
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    if (Status s = checkTool(tool); !s) return s;
    Operation operation;
    operation.kind = OperationKind::LatticeTools;
    operation.label = "add lattice " + tool.name;
    operation.toolIndex = static_cast<int>(s_.tools_.list.size());
    operation.toolAfter = tool;
    operation.frozenBefore = operation.frozenAfter = s_.tools_.frozen;
    return pushChange(std::move(operation), report);
}

Status ToolLibrary::edit(int index, const LatticeTool& tool, OpReport& report) {
    report = OpReport{};
    report.op = "edit_lattice";
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    if (index < 0 || index >= static_cast<int>(s_.tools_.list.size())) return Status::error("there is no lattice " + std::to_string(index));
    if (index == s_.tools_.frozen)
        return Status::error("lattice " + s_.tools_.list[static_cast<size_t>(index)].name + " is frozen: unfreeze it before editing its shape");
    if (Status s = checkTool(tool); !s) return s;
    Operation operation;
    operation.kind = OperationKind::LatticeTools;
    operation.label = "edit lattice " + tool.name;
    operation.toolIndex = index;
    operation.toolBefore = s_.tools_.list[static_cast<size_t>(index)];
    operation.toolAfter = tool;
    operation.frozenBefore = operation.frozenAfter = s_.tools_.frozen;
    return pushChange(std::move(operation), report);
}

Status ToolLibrary::remove(int index, OpReport& report) {
    report = OpReport{};
    report.op = "remove_lattice";
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    if (index < 0 || index >= static_cast<int>(s_.tools_.list.size())) return Status::error("there is no lattice " + std::to_string(index));
    if (index == s_.tools_.frozen) return Status::error("lattice " + s_.tools_.list[static_cast<size_t>(index)].name + " is frozen: unfreeze it first");
    Operation operation;
    operation.kind = OperationKind::LatticeTools;
    operation.label = "remove lattice " + s_.tools_.list[static_cast<size_t>(index)].name;
    operation.toolIndex = index;
    operation.toolBefore = s_.tools_.list[static_cast<size_t>(index)];
    operation.frozenBefore = s_.tools_.frozen;
    operation.frozenAfter = s_.tools_.frozen > index ? s_.tools_.frozen - 1 : s_.tools_.frozen;
    return pushChange(std::move(operation), report);
}

Status ToolLibrary::freeze(int index, int pinLayers, OpReport& report) {
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (index < 0 || index >= static_cast<int>(s_.tools_.list.size())) return Status::error("there is no lattice " + std::to_string(index));
    LatticeSettings settings;
    settings.volume = s_.tools_.list[static_cast<size_t>(index)].volume;
    settings.pinLayers = pinLayers;
    if (Status s = validateLatticeSettings(settings); !s) return s;
    // Freezing a lattice that holds no vertex would do nothing but replace the cage: say so instead.
    {
        const Volume& volume = *settings.volume;
        const Eigen::AlignedBox3d box = volume.restBounds();
        bool holds = false;
        for (Eigen::Index v = 0; v < s_.mesh_.positions.rows() && !holds; ++v) {
            const Eigen::Vector3d x = s_.mesh_.positions.row(v).transpose();
            Eigen::Vector3d t;
            holds = box.contains(x) && volume.freeze(x, t);
        }
        if (!holds)
            return Status::error("lattice " + s_.tools_.list[static_cast<size_t>(index)].name +
                                 " holds none of the mesh's vertices: place it over the part to deform (Place on mesh in the Lattices panel, \"place\" in scripts)");
    }
    const int before = s_.tools_.frozen;
    if (Status s = s_.setupLattice(settings, report); !s) return s;
    report.op = "freeze";
    if (report.status != OpStatus::Applied) return Status::success();
    s_.tools_.frozen = index;
    Operation& operation = s_.history_.last();
    operation.label = "freeze lattice " + s_.tools_.list[static_cast<size_t>(index)].name;
    operation.frozenBefore = before;
    operation.frozenAfter = index;
    s_.history_.lastJournaled().label = operation.label;
    s_.history_.lastJournaled().frozenBefore = before;
    s_.history_.lastJournaled().frozenAfter = index;
    int inside = s_.stack_.embedding_.insideCount();
    report.reason = "froze " + std::to_string(inside) + " of " + std::to_string(s_.mesh_.positions.rows()) + " vertices in lattice " +
                    s_.tools_.list[static_cast<size_t>(index)].name;
    return Status::success();
}

Status ToolLibrary::unfreeze(OpReport& report) {
    if (s_.tools_.frozen < 0) {
        report = OpReport{};
        report.op = "unfreeze";
        report.status = OpStatus::NoOp;
        report.reason = "no lattice is frozen";
        return Status::success();
    }
    const int before = s_.tools_.frozen;
    LatticeSettings box = s_.stack_.initialSettings_;
    box.hasRegion = false;  // around the mesh as it is now
    if (Status s = s_.setupLattice(box, report); !s) return s;
    report.op = "unfreeze";
    if (report.status != OpStatus::Applied) return Status::success();
    s_.tools_.frozen = -1;
    Operation& operation = s_.history_.last();
    operation.label = "unfreeze lattice " + s_.tools_.list[static_cast<size_t>(before)].name;
    operation.frozenBefore = before;
    operation.frozenAfter = -1;
    s_.history_.lastJournaled().label = operation.label;
    s_.history_.lastJournaled().frozenBefore = before;
    s_.history_.lastJournaled().frozenAfter = -1;
    return Status::success();
}

}  // namespace sculpt::core
