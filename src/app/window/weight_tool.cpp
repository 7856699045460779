// The window's hammer and crimp (sculpting by weights on a frozen weighted T-spline, Song & Yang 2005 sec. 1 and 6;
// Session::tspline().sculptWeights): a click becomes the script op a user would write, run through io::runScriptOp so the
// window and scripts share one command and one undo step.
#include <cmath>
#include <cstdio>

#include "app/window/tool_commands.h"
#include "io/script.h"

namespace sculpt::app {

void weightToolCommand(AppState& state, int vertex, double radius, bool invert) {
    if (state.drag.active) return;
    const BrushTool& brush = state.tools.brush;
    io::ScriptOp op;
    core::WeightToolSettings& tool = op.weightTool;
    tool.vertex = vertex;
    tool.radius = std::isfinite(radius) && radius > 0.0 ? radius : 0.0;
    std::string what;
    double hammerFrom = 0.0;
    if (brush.kind == BrushTool::Kind::Hammer) {
        op.kind = io::ScriptOp::Kind::Hammer;
        // The clicked vertex's height now (0 where nothing is raised), raised or lowered by one step.
        core::TSplineTools::Bump bump;
        tool.tool = core::WeightToolSettings::Tool::Hammer;
        double height = 0.0;
        if (state.session.tspline().bumpAt(tool, bump))
            for (size_t c = 0; c < bump.vertices.size(); ++c)
                if (bump.vertices[c] == vertex) height = bump.heights[c];
        const Eigen::Vector3d size = state.session.mesh().positions.colwise().maxCoeff() - state.session.mesh().positions.colwise().minCoeff();
        // note: a height below 1e-9 of the mesh's size is rounding (1e-21 on an untouched surface): shown as 0.
        if (std::abs(height) <= 1e-9 * size.norm()) height = 0.0;
        tool.hasHeight = true;
        tool.height = height + (invert ? -1.0 : 1.0) * brush.hammerStep * size.norm();
        hammerFrom = height;
    } else {
        op.kind = io::ScriptOp::Kind::Crimp;
        tool.tool = core::WeightToolSettings::Tool::Crimp;
        tool.widthFactor = invert ? 1.0 / brush.crimpFactor : brush.crimpFactor;
        char text[96];
        std::snprintf(text, sizeof text, "Crimp at vertex %d: width x%.3g, height kept", vertex, tool.widthFactor);
        what = text;
    }
    core::OpReport report;
    const Status s = io::runScriptOp(state.session, op, report);
    if (brush.kind == BrushTool::Kind::Hammer) {
        // The height reached: the bump scales linearly with the part of the raise applied (a fold stops it short).
        const double reached = hammerFrom + report.fractionApplied * (tool.height - hammerFrom);
        char text[128];
        std::snprintf(text, sizeof text, "Hammer at vertex %d: height %.4g -> %.4g", vertex, hammerFrom, reached);
        what = text;
    }
    if (s && report.status == core::OpStatus::Applied) {
        noteSessionMoved(state);
        state.hasReport = true;
        state.lastReport = report;
        state.stats.solveMs = report.wallMs;
        setStatus(state, what + " (" + report.reason + ").", false);
    } else {
        reportOperation(state, report, s);  // named from report.op: "Hammer", "Crimp"
    }
    state.gpu.fields = true;
}

}  // namespace sculpt::app
