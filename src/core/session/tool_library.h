// ToolLibrary: the lattices of any shape kept with the mesh as tools (Coquillart 1990, EFFD, section 3), and which
// of them is frozen as the cage. One per Session (Session::tools()). Each change of the list, a freeze and an
// unfreeze is one history operation: undoable and recorded. A tool that is frozen cannot be edited or removed
// (unfreeze it first). Files: tool_library.cpp; the tools' shapes and their library files are volume/ and io/.
#pragma once

#include <vector>

#include "core/session/operation.h"
#include "core/status.h"
#include "core/volume/lattice.h"

namespace sculpt::core {

class Session;

class ToolLibrary {
public:
    // What the library holds, kept by the session (a session copies and moves as one value).
    struct State {
        std::vector<LatticeTool> list;
        int frozen = -1;
    };
    // A handle on `session`'s library (Session::tools()), made per call.
    explicit ToolLibrary(Session& session) : s_(session) {}

    // The tools, in the order they were added (indices as the commands below take them).
    const std::vector<LatticeTool>& list() const;
    // The frozen tool, -1 when the box lattice is the cage.
    int frozen() const;
    // Adds, replaces or removes tool `index`. Errors (change nothing): a drag in progress, an index out of range, a
    // tool with no lattice or no name, editing or removing the frozen tool.
    Status add(const LatticeTool& tool, OpReport& report);
    Status edit(int index, const LatticeTool& tool, OpReport& report);
    Status remove(int index, OpReport& report);
    // Freezing (Coquillart 1990, 3.3): tool `index` becomes the cage. Every vertex inside it gets its parameters by
    // Newton's method, vertices outside every chunk do not move; drags, control-point moves, pins and undo then
    // work on its basis functions (3.4). The box lattice and any earlier deformation are frozen underneath (a
    // lattice set-up: undo returns to them). pinLayers: outer layers of points kept fixed, counted from the
    // tool's boundary faces (3.4: two fixed planes give a C1 seam where the lattice crosses the surface).
    // Errors: no mesh, an index out of range, bad settings, a tool that holds none of the mesh's vertices.
    Status freeze(int index, int pinLayers, OpReport& report);
    // Unfreezing: the deformation stays and a box lattice with the session's first settings is put around the
    // mesh again. NoOp when no tool is frozen.
    Status unfreeze(OpReport& report);

private:
    friend class Session;
    friend class TSplineTools;

    // Applies (forward) or takes back a LatticeTools operation's change of the list.
    void applyChange(const Operation& operation, bool forward);
    // Applies a new LatticeTools operation and pushes it onto the history.
    Status pushChange(Operation operation, OpReport& report);

    Session& s_;
};

}  // namespace sculpt::core
