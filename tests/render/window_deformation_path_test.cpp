// The window deforms a big mesh on the faster of two paths (app/deformation_path.h): it times frames of both
// during the first drag, keeps one, says which in the stats panel, and both draw the same mesh.
#include <catch2/catch.hpp>

#include "gl_test_support.h"
#include "window_test_support.h"

using namespace sculpt;
using namespace sculpt::test;

namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

void requireOk(const Status& status) {
    INFO(status.message);
    REQUIRE(status.ok);
}

}  // namespace

TEST_CASE("window: a drag times both deformation paths, keeps the faster, and both draw the same mesh", "[gl][window]") {
    app::SculptApp sculptApp;
    OffscreenWindow window;
    app::AppState& state = sculptApp.state();
    state.deformationPath.setMinVertices(0);  // the default mesh is small: measure it anyway
    if (!openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return;
    requireOk(window.frame());
    REQUIRE(state.deformationPath.deciding());
    CHECK_FALSE(sculptApp.renderer().gpuDeformationActive());  // at rest on the CPU until both are timed
    CHECK(state.stats.deformationPath == "CPU");
    CHECK(state.deformationPath.stillMs(app::DeformationPath::Cpu) >= 0.0);  // its still frame was timed

    // A drag from the centre of the view upward, one frame per mouse move.
    double x = 0.5 * kWidth, y = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
    REQUIRE(state.drag.active);
    bool sawGpu = false, sawCpu = false;
    for (int step = 0; step < 30 && state.deformationPath.deciding(); ++step) {
        y -= 2.0;
        sculptApp.onMouseMove({x, y, {}}, {});
        requireOk(window.frame());
        const bool onGpu = sculptApp.renderer().gpuDeformationActive();
        (onGpu ? sawGpu : sawCpu) = true;
        if (state.deformationPath.deciding()) CHECK(state.stats.deformationPath == (onGpu ? "GPU (timing)" : "CPU (timing)"));
        // Picking and the engine keep exact positions on either path: the renderer is told nothing else.
        CHECK(state.session.mesh().positions.allFinite());
    }
    CHECK(sawGpu);
    CHECK(sawCpu);
    REQUIRE_FALSE(state.deformationPath.deciding());
    CHECK(state.deformationPath.medianMs(app::DeformationPath::Gpu) >= 0.0);
    CHECK(state.deformationPath.medianMs(app::DeformationPath::Cpu) >= 0.0);
    sculptApp.onMouseMove({x, y - 2.0, {}}, {});
    requireOk(window.frame());
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y - 2.0, {}}, {});
    requireOk(window.frame());
    requireOk(window.frame());  // (a GPU win times its still frame once, then settles)
    const bool gpu = state.deformationPath.restPath() == app::DeformationPath::Gpu;
    CHECK(sculptApp.renderer().gpuDeformationActive() == gpu);
    // The stats panel says which, and its tooltip the times it compared.
    CHECK((state.stats.deformationPath == "GPU" || state.stats.deformationPath == "CPU" ||
           state.stats.deformationPath == "GPU drag, CPU rest"));
    CHECK(state.stats.deformationDetails.find("Drag frames (median): GPU ") != std::string::npos);
    CHECK(state.stats.deformationDetails.find("Drag frames (median): GPU not timed") == std::string::npos);
    CHECK(state.stats.deformationDetails.find("CPU not timed.\nStill") == std::string::npos);
    REQUIRE(state.session.history().size() == 1);

    // Both paths draw the same dragged mesh (within the golden threshold), and the CPU picture is exact again
    // after a round trip. Scene only: the panels' numbers differ.
    state.stats.hideTimings = true;
    state.deformationPath.force(app::DeformationPath::Cpu);
    render::Rgba8Image cpu, viaGpu, back;
    requireOk(window.frame(&cpu));
    CHECK_FALSE(sculptApp.renderer().gpuDeformationActive());
    state.deformationPath.force(app::DeformationPath::Gpu);
    requireOk(window.frame(&viaGpu));
    CHECK(sculptApp.renderer().gpuDeformationActive());
    CHECK(state.stats.deformationPath == "GPU (chosen)");
    state.deformationPath.force(app::DeformationPath::Cpu);
    requireOk(window.frame(&back));
    CHECK(differingFraction(cpu, viaGpu) <= goldenMaxDifferingFraction());
    CHECK(differingFraction(cpu, back) == 0.0);

    // Undo on the GPU path: the rest mesh stays, the lattice goes back, the picture is the undeformed one.
    state.deformationPath.force(app::DeformationPath::Gpu);
    requireOk(window.frame());
    const Positions dragged = state.session.mesh().positions;
    app::KeyEvent ctrlZ;
    ctrlZ.key = app::Key::Z;
    ctrlZ.modifiers.control = true;
    sculptApp.onKey(ctrlZ, {});
    REQUIRE(state.session.history().cursor() == 0);
    render::Rgba8Image undone, undoneCpu;
    requireOk(window.frame(&undone));
    CHECK(sculptApp.renderer().gpuDeformationActive());
    state.deformationPath.force(app::DeformationPath::Cpu);
    requireOk(window.frame(&undoneCpu));
    CHECK(differingFraction(undone, undoneCpu) <= goldenMaxDifferingFraction());
    CHECK(differingFraction(undone, viaGpu) > 0.001);  // the undo shows
}
