#include "app/headless.h"

#include <chrono>
#include <cstdio>
#include <iostream>

#include "app/screenshot_hook.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/atomic_file.h"
#include "io/mesh_file.h"
#include "io/mesh_weld.h"
#include "io/script_json.h"

namespace sculpt::app {

int runHeadless(const CliOptions& options, const char* argv0) {
    io::Script script;
    if (Status s = io::loadScript(options.script, script); !s) {
        std::cerr << "sculpt: " << s.message << "\n";
        return kExitBadInput;
    }
    // --input, else the mesh the script names (a saved session), else the bundled default mesh.
    std::string input = options.input.empty() ? io::resolveScriptMesh(script, options.script) : options.input;
    if (input.empty()) input = defaultMeshPath(argv0);
    io::ObjMesh mesh;
    std::vector<std::string> warnings;
    const auto loadStart = std::chrono::steady_clock::now();
    // The output's format comes from its name: refuse an unknown one before any work is done.
    io::MeshEncoding outputEncoding;
    if (Status s = io::meshEncodingForPath(options.output, outputEncoding); !s) {
        std::cerr << "sculpt: --output " << s.message << "\n";
        return kExitBadInput;
    }
    if (Status s = io::loadMesh(input, mesh, &warnings); !s) {
        std::cerr << "sculpt: " << s.message << "\n";
        return kExitBadInput;
    }
    for (const std::string& w : warnings) std::cerr << "sculpt: warning: " << w << "\n";
    const bool weld = options.weld || script.weldMesh;
    if (weld) {
        const io::WeldReport welded = io::weldCoincidentVertices(mesh);
        if (welded.verticesAfter < welded.verticesBefore)
            std::printf("welded %s: %d vertices at %d positions\n", input.c_str(), welded.verticesBefore, welded.verticesAfter);
    } else if (const io::WeldReport coincident = io::countCoincidentVertices(mesh.positions);
               coincident.verticesAfter < coincident.verticesBefore) {
        std::cerr << "sculpt: warning: " << input << ": " << coincident.verticesBefore - coincident.verticesAfter
                  << " vertices lie exactly on another (a triangle soup or split seams); --weld joins them\n";
    }
    const double loadMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - loadStart).count();

    core::Session session;
    if (Status s = session.setMesh(mesh.positions, mesh.triangles, script.lattice); !s) {
        std::cerr << "sculpt: " << input << ": " << s.message << "\n";
        return kExitBadInput;
    }
    session.setInjectivity(script.injectivity);
    // The det J colour map shows the whole deformation, across the fresh lattices of subdivided operations.
    for (const std::string& overlay : options.overlays)
        if (overlay == "jacobian") session.setTrackJacobian(true);
    std::printf("loaded %s: %d vertices, %d triangles (%.0f ms); lattice %dx%dx%d, degree %d/%d/%d\n", input.c_str(),
                static_cast<int>(mesh.positions.rows()), static_cast<int>(mesh.triangles.rows()), loadMs,
                session.lattice().count[0], session.lattice().count[1], session.lattice().count[2],
                session.lattice().degree[0], session.lattice().degree[1], session.lattice().degree[2]);
    if (session.meshAsSet().degenerateTriangles > 0)
        std::cerr << "sculpt: warning: " << input << " has " << session.meshAsSet().degenerateTriangles
                  << " degenerate (zero-area) facet(s); they are not counted as crossings\n";
    if (session.meshAsSet().intersectingPairs > 0)
        std::cerr << "sculpt: warning: " << input << " already crosses itself (" << session.meshAsSet().intersectingPairs
                  << " triangle pairs); those never count against an edit, only new crossings are refused\n";

    ScreenshotRenderer screenshots(options);
    io::ScriptReport report;
    const io::ScreenshotHook hook = [&](const core::Session& current, const io::ScriptOp& op) {
        return screenshots.capture(current, op.path, &mesh);
    };
    if (Status s = io::runScript(session, script, report, hook); !s) {
        std::cerr << "sculpt: " << options.script << ": " << s.message << "\n";
        std::cerr << "sculpt: nothing was written\n";
        return kExitBadInput;
    }
    for (size_t i = 0; i < report.ops.size(); ++i) {
        const core::OpReport& r = report.ops[i];
        std::printf("  op %zu %-18s %-8s %s%s (%.2f ms", i, r.op.c_str(), core::opStatusName(r.status), r.reason.c_str(),
                    r.subSteps > 1 ? (" [" + std::to_string(r.subSteps) + " injective steps]").c_str() : "", r.wallMs);
        std::printf(")\n");
    }

    // A refined session writes the refined mesh, texture coordinates interpolated at the splits.
    std::vector<std::string> saveWarnings;
    if (Status s = io::saveRefinedMesh(options.output, mesh, session.refinement().appliedSplits(), session.mesh().positions, &saveWarnings);
        !s) {
        std::cerr << "sculpt: " << s.message << "\n";
        return kExitWriteFailed;
    }
    for (const std::string& w : saveWarnings) std::cerr << "sculpt: warning: " << w << "\n";
    std::printf("wrote %s\n", options.output.c_str());
    if (!options.report.empty()) {
        io::ReportContext context{input, options.script, options.output, static_cast<int>(mesh.positions.rows()),
                                  static_cast<int>(mesh.triangles.rows()),
                                  (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).norm()};
        if (Status s = io::writeFileAtomically(options.report, io::reportToJson(report, session, context)); !s) {
            std::cerr << "sculpt: " << s.message << "\n";
            return kExitWriteFailed;
        }
        std::printf("wrote %s\n", options.report.c_str());
    }
    if (!options.saveSession.empty()) {
        io::Script recorded = io::recordSession(session);
        recorded.mesh = io::scriptRelativeMeshPath(input, options.saveSession);
        recorded.weldMesh = weld;
        if (Status s = io::writeFileAtomically(options.saveSession, io::scriptToJson(recorded)); !s) {
            std::cerr << "sculpt: " << s.message << "\n";
            return kExitWriteFailed;
        }
        std::printf("wrote %s\n", options.saveSession.c_str());
    }
    if (!options.screenshot.empty()) {
        if (Status s = screenshots.capture(session, options.screenshot, &mesh); !s) {
            std::cerr << "sculpt: " << s.message << "\n";
            return kExitWriteFailed;
        }
        std::printf("wrote %s\n", options.screenshot.c_str());
    }
    return kExitOk;
}

}  // namespace sculpt::app
