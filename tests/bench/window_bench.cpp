#include "window_bench.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <numeric>
#include <vector>

#include "../render/offscreen_window.h"
#include "../render/test_meshes.h"
#include "app/window/sculpt_app.h"
#include "bench_support.h"
#include "render/gl_functions.h"

namespace sculpt::bench {

namespace {

constexpr int kWidth = 1280, kHeight = 800;  // the window's default size
constexpr double kPixelsPerMove = 2.0;       // a slow, steady drag: one mouse event per frame

using Clock = std::chrono::steady_clock;

double msBetween(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

bool wanted(const std::vector<std::string>& filters, const std::string& name) {
    if (filters.empty()) return true;
    for (const std::string& f : filters)
        if (name.find(f) != std::string::npos) return true;
    return false;
}


// Loads the mesh into the app's session (lattice `resolution`^3, default degree and injectivity) and frames
// it in a kWidth x kHeight view.
Status loadInto(app::SculptApp& sculptApp, const test::TestMesh& mesh, const std::string& name, int resolution) {
    core::LatticeSettings settings;
    settings.resolution = {resolution, resolution, resolution};
    if (Status s = app::setMesh(sculptApp.state(), mesh.positions, mesh.triangles, name, settings); !s) return s;
    sculptApp.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(sculptApp.state());
    return Status::success();
}

// Frames per second of the full window path (engine, GPU update, scene and panels drawn, GL finished) while
// the centre of a UV sphere is dragged up, one mouse move per frame.
// The engine's share is reported on its own (engine_ms: solve, injectivity and triangle checks, evaluation;
// triangle_check_ms its part), and draw_fps is the rate the window's drawing alone would allow.
// proxy false: the whole mesh in every frame (what the proxy saves).
void benchDragFrames(std::ostream& out, const char* name, const test::TestMesh& sphere, int resolution, bool proxy = true) {
    app::SculptApp sculptApp;
    if (Status s = loadInto(sculptApp, sphere, name, resolution); !s) return printError(out, name, s.message);
    test::OffscreenWindow window;
    if (Status s = window.open(sculptApp, kWidth, kHeight, 1); !s)
        return printError(out, name, "no EGL window, skipped: " + s.message);
    if (!proxy) {
        render::MeshProxyOptions never;
        never.minTriangles = std::numeric_limits<int>::max();
        sculptApp.renderer().setMeshProxyOptions(never);
    }
    // The first frames build the font atlas and upload the mesh; then frames with nothing to update.
    for (int f = 0; f < 3; ++f)
        if (Status s = window.frame(); !s) return printError(out, name, s.message);
    std::vector<double> idle;
    for (int f = 0; f < 10; ++f) {
        const auto start = Clock::now();
        window.frame();
        idle.push_back(msBetween(start, Clock::now()));
    }

    app::AppState& state = sculptApp.state();
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    if (!state.drag.active) return printError(out, name, "the press at the centre did not grab the mesh");
    const int warmup = 3, moves = 40;
    std::vector<double> engine, triangleCheck, update, draw, finish, total, drawing, moved, uploaded, drawnTriangles;
    for (int m = 1; m <= warmup + moves; ++m) {
        const auto start = Clock::now();
        sculptApp.onMouseMove({cx, cy - kPixelsPerMove * m, {}}, {});
        const auto moveDone = Clock::now();
        if (Status s = window.renderOnly(); !s) return printError(out, name, s.message);
        const auto drawn = Clock::now();
        window.finish();
        const auto finished = Clock::now();
        if (m <= warmup) continue;
        engine.push_back(msBetween(start, moveDone));
        triangleCheck.push_back(state.lastReport.triangleCheckMs);
        drawing.push_back(msBetween(moveDone, finished));
        drawnTriangles.push_back(sculptApp.renderer().lastDrawnTriangles());
        update.push_back(state.stats.updateMs);
        draw.push_back(state.stats.renderMs);
        finish.push_back(msBetween(drawn, finished));
        total.push_back(msBetween(start, finished));
        moved.push_back(static_cast<double>(state.session.lastMoved().all ? state.session.mesh().positions.rows()
                                                                        : state.session.lastMoved().vertices.size()));
        uploaded.push_back(state.stats.lastUploadVertices);
    }
    const int refused = state.drag.refused;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - kPixelsPerMove * moves, {}}, {});
    const double frameMs = median(total);
    // The first frame after the release: the whole mesh again, normals and all.
    const auto releasedStart = Clock::now();
    window.frame();
    const double releasedMs = msBetween(releasedStart, Clock::now());
    char line[1024];
    std::snprintf(line, sizeof line,
                  "{\"case\": \"%s\", \"n\": %d, \"vertices\": %d, \"fps\": %.1f, \"median_ms\": %.2f, "
                  "\"draw_fps\": %.1f, \"drawn_triangles\": %.0f, \"lattice\": %d, "
                  "\"engine_ms\": %.2f, \"triangle_check_ms\": %.2f, \"gpu_update_ms\": %.2f, \"draw_ms\": %.2f, \"finish_ms\": %.2f, "
                  "\"idle_frame_ms\": %.2f, \"release_frame_ms\": %.2f, \"vertices_moved\": %.0f, \"vertices_uploaded\": %.0f, \"moves\": %d, "
                  "\"refused\": %d, \"width\": %d, \"height\": %d, \"msaa\": 0, \"ui\": true, \"backend\": \"%s\"}",
                  name, static_cast<int>(sphere.triangles.rows()), static_cast<int>(sphere.positions.rows()),
                  1000.0 / frameMs, frameMs, 1000.0 / median(drawing), median(drawnTriangles), resolution,
                  median(engine), median(triangleCheck), median(update), median(draw), median(finish), median(idle),
                  releasedMs, median(moved), median(uploaded), moves, refused, kWidth, kHeight,
                  jsonText(window.context().description()).c_str());
    out << line << std::endl;
}

void benchDragEngine(std::ostream& out, const char* name, const test::TestMesh& sphere, int resolution) {
    app::SculptApp sculptApp;
    if (Status s = loadInto(sculptApp, sphere, "sphere_1m", resolution); !s) return printError(out, name, s.message);
    app::AppState& state = sculptApp.state();
    // The GPU side where EGL exists: one frame uploads the whole mesh (syncGpu's setMesh), then each move's
    // sparse upload is timed on its own, exactly what the next frame's syncGpu sends for it.
    test::OffscreenWindow window;
    const Status windowOpen = window.open(sculptApp, kWidth, kHeight, 1);
    const bool gpu = windowOpen && window.frame();

    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    const auto pressStart = Clock::now();
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    const double pressMs = msBetween(pressStart, Clock::now());
    if (!state.drag.active) return printError(out, name, "the press at the centre did not grab the mesh");
    const int warmup = 2, moves = 20;
    std::vector<double> engine, solve, upload, moved;
    std::vector<int> all;
    for (int m = 1; m <= warmup + moves; ++m) {
        const auto start = Clock::now();
        sculptApp.onMouseMove({cx, cy - kPixelsPerMove * m, {}}, {});
        const double engineMs = msBetween(start, Clock::now());
        double uploadMs = 0.0;
        app::PendingGpuUpdate& pending = state.gpu;
        if (gpu) {
            if (pending.allPositions && all.empty()) {
                all.resize(static_cast<size_t>(state.session.mesh().positions.rows()));
                std::iota(all.begin(), all.end(), 0);
            }
            const auto uploadStart = Clock::now();
            sculptApp.renderer().updatePositions(state.session.mesh().positions, pending.allPositions ? all : pending.vertices);
            window.context().gl().Finish();
            uploadMs = msBetween(uploadStart, Clock::now());
        }
        // Drained as a frame would, so the pending list holds one move's vertices at a time.
        pending.allPositions = false;
        pending.vertices.clear();
        if (m <= warmup) continue;
        engine.push_back(engineMs);
        solve.push_back(state.lastReport.wallMs);
        upload.push_back(uploadMs);
        moved.push_back(static_cast<double>(state.session.lastMoved().all ? state.session.mesh().positions.rows()
                                                                        : state.session.lastMoved().vertices.size()));
    }
    const int refused = state.drag.refused;
    const auto releaseStart = Clock::now();
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - kPixelsPerMove * moves, {}}, {});
    const double releaseMs = msBetween(releaseStart, Clock::now());
    char uploadText[32] = "null";
    if (gpu) std::snprintf(uploadText, sizeof uploadText, "%.2f", median(upload));
    char line[1024];
    std::snprintf(line, sizeof line,
                  "{\"case\": \"%s\", \"n\": %d, \"median_ms\": %.2f, \"session_update_drag_ms\": %.2f, "
                  "\"sparse_upload_ms\": %s, \"vertices_moved\": %.0f, \"fraction_moved\": %.3f, \"press_ms\": %.1f, "
                  "\"release_ms\": %.1f, \"moves\": %d, \"refused\": %d, \"lattice\": %d}",
                  name, static_cast<int>(sphere.positions.rows()), median(engine), median(solve),
                  uploadText, median(moved),
                  median(moved) / static_cast<double>(sphere.positions.rows()), pressMs, releaseMs, moves, refused,
                  resolution);
    out << line << std::endl;
    if (!gpu)
        std::fprintf(stderr, "%s: no EGL window, sparse upload not measured: %s\n", name,
                     windowOpen ? "first frame failed" : windowOpen.message.c_str());
}

// The real program idle under Xvfb (issue: an idle window sleeps): `sculpt MESH` with
// SCULPT_WINDOW_IDLE_SECONDS, which opens the mesh, waits until it is drawn, then measures the process's CPU
// time and the frames drawn over that many seconds with no input.
void benchIdleWindow(std::ostream& out, const char* name, const std::string& mesh, int seconds) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
        printError(out, name, "xvfb-run is not installed (apt-get install xvfb xauth)");
        return;
    }
    const std::string command = "SCULPT_WINDOW_IDLE_SECONDS=" + std::to_string(seconds) +
                                " xvfb-run -a -s '-screen 0 1280x800x24' '" SCULPT_PROGRAM "' '" + mesh + "' 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) {
        printError(out, name, "cannot run " + command);
        return;
    }
    std::string output;
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
    pclose(pipe);
    double measured = 0.0, share = 0.0;
    long frames = -1;
    const size_t at = output.find("sculpt: idle ");
    if (at == std::string::npos ||
        std::sscanf(output.c_str() + at, "sculpt: idle %lf s: %lf%% of one core, %ld frames drawn", &measured, &share,
                    &frames) != 3) {
        printError(out, name, "no measurement in the program's output: " + output);
        return;
    }
    out << "{\"case\": \"" << name << "\", \"mesh\": \"" << jsonText(mesh) << "\", \"seconds\": " << measured
        << ", \"core_share_percent\": " << share << ", \"frames_drawn\": " << frames << "}" << std::endl;
}

}  // namespace

void runWindowBenchmarks(std::ostream& out, const std::vector<std::string>& filters) {
    if (wanted(filters, "window_drag_100k"))
        benchDragFrames(out, "window_drag_100k", test::makeUvSphere(250, 201), 8);  // 2 * 250 * 200 = 100,000 triangles
    if (wanted(filters, "window_drag_250k"))
        benchDragFrames(out, "window_drag_250k", test::makeUvSphere(500, 501), 16);  // 250,002 vertices, 500,000 triangles
    if (wanted(filters, "window_drag_250k_whole"))
        benchDragFrames(out, "window_drag_250k_whole", test::makeUvSphere(500, 501), 16, false);
    if (wanted(filters, "window_idle")) {
        benchIdleWindow(out, "window_idle_default", SCULPT_SOURCE_DIR "/assets/default.obj", 10);
        // CGAL's armadillo scan (26k vertices), where the polling loop took 1.7 cores.
        const std::string folder = "/tmp/sculpt_bench_cgal";
        const std::string extract = "mkdir -p " + folder + " && tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C " +
                                    folder + " data/meshes/armadillo.off 2> /dev/null";
        if (std::system(extract.c_str()) == 0)
            benchIdleWindow(out, "window_idle_armadillo", folder + "/data/meshes/armadillo.off", 10);
        else
            printError(out, "window_idle_armadillo", "CGAL's data is not installed (libcgal-demo)");
    }
    const bool engine8 = wanted(filters, "window_drag_1m_engine");
    const bool engine16 = wanted(filters, "window_drag_1m_engine_16");
    if (!engine8 && !engine16) return;
    const test::TestMesh sphere = test::makeUvSphere(1000, 1001);  // 1,000,002 vertices, 2M triangles
    if (engine8) benchDragEngine(out, "window_drag_1m_engine", sphere, 8);
    if (engine16) benchDragEngine(out, "window_drag_1m_engine_16", sphere, 16);
}

}  // namespace sculpt::bench

