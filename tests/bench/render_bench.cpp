#include "render_bench.h"

#include "bench_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <vector>

#include "../render/test_meshes.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"
#include "core/deform/vertex_normals.h"
#include "render/offscreen_renderer.h"

namespace sculpt::render {

namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 800;
constexpr int kSamples = 4;
constexpr int kRuns = 10;

using bench::jsonText;
using bench::medianMs;
using bench::printError;


// Camera at the distance where a unit sphere's silhouette touches the top and bottom of the picture:
// a disc of diameter = picture height, i.e. pi/4 * 800/1280 = 49% of the pixels.
Camera halfScreenCamera() {
    Camera camera;
    camera.target = glm::vec3(0.0f);
    camera.sceneRadius = 1.0f;
    camera.distance = 1.0f / std::sin(glm::radians(camera.fovYDeg) * 0.5f);
    return camera;
}

void benchFrames(std::ostream& out, OffscreenRenderer& offscreen, const char* name, int segments, int rings,
                 int samples = kSamples) {
    const test::TestMesh sphere = test::makeUvSphere(segments, rings);
    Renderer& renderer = offscreen.renderer();
    if (Status status = renderer.setMesh(sphere.positions, sphere.triangles); !status)
        return printError(out, name, status.message);
    const Camera camera = halfScreenCamera();
    DrawOptions options;
    Status failed;
    // Coverage check from one read-back frame (background pixels have alpha 0 with background off).
    DrawOptions noBackground = options;
    noBackground.background = false;
    Rgba8Image image;
    if (Status status = offscreen.render(camera, noBackground, kWidth, kHeight, samples, &image); !status)
        return printError(out, name, status.message);
    long covered = 0;
    for (size_t p = 3; p < image.pixels.size(); p += 4) covered += image.pixels[p] > 0;
    const double ms = medianMs(kRuns, [&] {
        if (Status status = offscreen.render(camera, options, kWidth, kHeight, samples, nullptr); !status)
            failed = status;
    });
    if (!failed) return printError(out, name, failed.message);
    out << "{\"case\": \"" << name << "\", \"n\": " << sphere.triangles.rows() << ", \"fps\": " << 1000.0 / ms
        << ", \"median_ms\": " << ms << ", \"width\": " << kWidth << ", \"height\": " << kHeight
        << ", \"msaa\": " << samples << ", \"coverage\": " << double(covered) / (double(kWidth) * kHeight)
        << ", \"backend\": \"" << jsonText(offscreen.context().description()) << "\"}" << std::endl;
}

void benchUploads(std::ostream& out, OffscreenRenderer& offscreen) {
    // 1000 x 1001 latitude-longitude sphere: 1,000,002 vertices (2M triangles).
    const test::TestMesh sphere = test::makeUvSphere(1000, 1001);
    const int vertexCount = int(sphere.positions.rows());
    Renderer& renderer = offscreen.renderer();
    if (Status status = renderer.setMesh(sphere.positions, sphere.triangles); !status)
        return printError(out, "upload_1m", status.message);
    const auto& gl = offscreen.context().gl();
    Positions moved = sphere.positions;
    std::vector<int> all(static_cast<size_t>(vertexCount));
    for (int v = 0; v < vertexCount; ++v) all[size_t(v)] = v;
    Status failed;
    int step = 0;
    const double fullMs = medianMs(
        kRuns,
        [&] {
            if (Status status = renderer.updatePositions(moved, all); !status) failed = status;
            gl.Finish();  // the upload has reached the GL
        },
        [&] { moved = sphere.positions * (1.0 + 0.01 * ++step); });
    if (!failed) return printError(out, "upload_1m", failed.message);
    Positions normals;  // the renderer's way: the mesh's adjacency kept
    const core::VertexTriangles adjacency = core::buildVertexTriangles(vertexCount, sphere.triangles);
    const double normalsMs =
        medianMs(kRuns, [&] { core::computeVertexNormals(moved, sphere.triangles, adjacency, normals); });
    out << "{\"case\": \"upload_1m\", \"n\": " << vertexCount << ", \"median_ms\": " << fullMs
        << ", \"normals_ms\": " << normalsMs << ", \"full_upload\": " << (renderer.lastUpload().fullUpload ? "true" : "false")
        << "}" << std::endl;

    // A local edit: 2% of the vertices, a cap around the north pole (vertices are stored by latitude, so it is
    // one contiguous range, like the engine's cell-sorted output).
    std::vector<int> cap(static_cast<size_t>(vertexCount / 50));
    for (size_t v = 0; v < cap.size(); ++v) cap[v] = int(v);
    const double localMs = medianMs(
        kRuns,
        [&] {
            if (Status status = renderer.updatePositions(moved, cap); !status) failed = status;
            gl.Finish();
        },
        [&] {
            const double scale = 1.0 + 0.01 * (++step % 7);
            for (int v : cap) moved.row(v) = sphere.positions.row(v) * scale;
        });
    if (!failed) return printError(out, "upload_1m_local", failed.message);
    const UploadStats stats = renderer.lastUpload();
    out << "{\"case\": \"upload_1m_local\", \"n\": " << cap.size() << ", \"median_ms\": " << localMs
        << ", \"vertices_uploaded\": " << stats.verticesUploaded << ", \"ranges\": " << stats.ranges << "}" << std::endl;
}

// full_update_1m (issue 12, point 3): what follows a fresh frame or a global drag on 1M vertices, end to end:
// every position evaluated (cubic 8^3 lattice, all control points displaced), every normal recomputed, the
// vertex buffer rewritten and the GL finished with it.
void benchFullUpdate(std::ostream& out, OffscreenRenderer& offscreen) {
    const test::TestMesh sphere = test::makeUvSphere(1000, 1001);  // 1,000,002 vertices, 2M triangles
    const int vertexCount = int(sphere.positions.rows());
    Renderer& renderer = offscreen.renderer();
    if (Status status = renderer.setMesh(sphere.positions, sphere.triangles); !status)
        return printError(out, "full_update_1m", status.message);
    core::LatticeSettings settings;  // 8^3 control points, cubic
    core::Lattice lattice;
    core::makeLattice(settings, sphere.positions, lattice);
    const core::Embedding embedding = core::embedVertices(lattice, sphere.positions);
    const auto& gl = offscreen.context().gl();
    std::vector<int> all(static_cast<size_t>(vertexCount));
    for (int v = 0; v < vertexCount; ++v) all[size_t(v)] = v;
    Positions positions = sphere.positions;
    std::vector<double> totalMs, evaluateMs, uploadMs;
    Status failed;
    for (int run = 0; run <= kRuns; ++run) {
        for (int c = 0; c < lattice.controlPointCount(); ++c)  // a new global change each run
            lattice.displacement.row(c) << 0.01 * std::sin(c + run), 0.01 * std::cos(c * 3 + run), 0.005 * run;
        const auto start = std::chrono::steady_clock::now();
        core::evaluateAll(lattice, embedding, positions);
        const auto evaluated = std::chrono::steady_clock::now();
        if (Status status = renderer.updatePositions(positions, all); !status) failed = status;
        gl.Finish();
        const auto end = std::chrono::steady_clock::now();
        if (run == 0) continue;  // warm-up
        evaluateMs.push_back(std::chrono::duration<double, std::milli>(evaluated - start).count());
        uploadMs.push_back(std::chrono::duration<double, std::milli>(end - evaluated).count());
        totalMs.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    }
    if (!failed) return printError(out, "full_update_1m", failed.message);
    const bool fullUpload = renderer.lastUpload().fullUpload;
    // The same update on the GPU path (Renderer::setGpuDeformation): the positions still evaluated in double for
    // the engine, then only the control displacements sent; the normals come from the vertex shader at draw time.
    std::vector<double> gpuPathMs;
    if (Status status = renderer.setGpuDeformation(lattice, embedding, sphere.positions); !status)
        return printError(out, "full_update_1m", status.message);
    for (int run = 0; run <= kRuns; ++run) {
        for (int c = 0; c < lattice.controlPointCount(); ++c)
            lattice.displacement.row(c) << 0.01 * std::cos(c + run), 0.01 * std::sin(c * 3 + run), 0.005 * run;
        const auto start = std::chrono::steady_clock::now();
        core::evaluateAll(lattice, embedding, positions);
        if (Status status = renderer.updateGpuDeformation(lattice); !status) failed = status;
        gl.Finish();
        if (run > 0) gpuPathMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    if (Status status = renderer.clearGpuDeformation(positions); !status) failed = status;
    if (!failed) return printError(out, "full_update_1m", failed.message);
    out << "{\"case\": \"full_update_1m\", \"n\": " << vertexCount << ", \"median_ms\": " << bench::median(totalMs)
        << ", \"evaluate_ms\": " << bench::median(evaluateMs) << ", \"normals_and_upload_ms\": " << bench::median(uploadMs)
        << ", \"full_upload\": " << (fullUpload ? "true" : "false")
        << ", \"gpu_path_ms\": " << bench::median(gpuPathMs) << "}" << std::endl;
}

// gpu_drag_1m / gpu_drag_10m (issue 12, point 1): frames per second while dragging globally, every vertex
// moving, on the CPU path and on the GPU path. A frame on either path: the engine evaluates every position
// (picking, saving and the injectivity checks use them), the renderer updates, a 1280 x 800 picture without
// MSAA (the window's on software GL) is drawn and finished. CPU path: normals, packing and the whole vertex
// buffer (updatePositions); GPU path: the control displacements only, the vertex shader deforms
// (updateGpuDeformation). gpu_only_ms leaves out the engine's evaluation.
void benchGpuDrag(std::ostream& out, OffscreenRenderer& offscreen, const char* name, int segments, int rings, int runs) {
    const test::TestMesh sphere = test::makeUvSphere(segments, rings);
    const int vertexCount = int(sphere.positions.rows());
    Renderer& renderer = offscreen.renderer();
    if (Status status = renderer.setMesh(sphere.positions, sphere.triangles); !status) return printError(out, name, status.message);
    core::LatticeSettings settings;  // 8^3 control points, cubic
    core::Lattice lattice;
    core::makeLattice(settings, sphere.positions, lattice);
    const core::Embedding embedding = core::embedVertices(lattice, sphere.positions);
    std::vector<int> all(static_cast<size_t>(vertexCount));
    for (int v = 0; v < vertexCount; ++v) all[size_t(v)] = v;
    Positions positions = sphere.positions;
    const Camera camera = halfScreenCamera();
    Status failed;
    const auto frames = [&](bool gpu, bool proxy, std::vector<double>& totalMs, std::vector<double>& rendererMs) {
        DrawOptions options;
        options.proxy = proxy;
        for (int run = 0; run <= runs; ++run) {
            for (int c = 0; c < lattice.controlPointCount(); ++c)  // a new global change each frame
                lattice.displacement.row(c) << 0.01 * std::sin(c + run), 0.01 * std::cos(c * 3 + run), 0.005 * run;
            const auto start = std::chrono::steady_clock::now();
            core::evaluateAll(lattice, embedding, positions);
            const auto evaluated = std::chrono::steady_clock::now();
            const Status status = gpu ? renderer.updateGpuDeformation(lattice) : renderer.updatePositions(positions, all);
            if (!status) failed = status;
            if (Status drawn = offscreen.render(camera, options, kWidth, kHeight, 1, nullptr); !drawn) failed = drawn;
            const auto end = std::chrono::steady_clock::now();
            if (run == 0) continue;  // warm-up (the first frame after a switch uploads everything)
            totalMs.push_back(std::chrono::duration<double, std::milli>(end - start).count());
            rendererMs.push_back(std::chrono::duration<double, std::milli>(end - evaluated).count());
        }
    };
    // The whole mesh drawn each frame, and the window's way during a drag: its decimated proxy (mesh_proxy.h,
    // an index buffer over the same vertices, so either path deforms it).
    std::vector<double> cpuMs, cpuRendererMs, gpuMs, gpuRendererMs, cpuProxyMs, gpuProxyMs, unused;
    frames(false, false, cpuMs, cpuRendererMs);
    frames(false, true, cpuProxyMs, unused);
    if (Status status = renderer.setGpuDeformation(lattice, embedding, sphere.positions); !status)
        return printError(out, name, status.message);
    frames(true, false, gpuMs, gpuRendererMs);
    frames(true, true, gpuProxyMs, unused);
    if (Status status = renderer.clearGpuDeformation(positions); !status) failed = status;
    if (!failed) return printError(out, name, failed.message);
    const double cpu = bench::median(cpuMs), gpu = bench::median(gpuMs);
    const double cpuProxy = bench::median(cpuProxyMs), gpuProxy = bench::median(gpuProxyMs);
    out << "{\"case\": \"" << name << "\", \"n\": " << vertexCount << ", \"cpu_fps\": " << 1000.0 / cpu
        << ", \"gpu_fps\": " << 1000.0 / gpu << ", \"cpu_frame_ms\": " << cpu << ", \"gpu_frame_ms\": " << gpu
        << ", \"cpu_update_and_draw_ms\": " << bench::median(cpuRendererMs)
        << ", \"gpu_update_and_draw_ms\": " << bench::median(gpuRendererMs) << ", \"gpu_speedup\": " << cpu / gpu
        << ", \"proxy_triangles\": " << renderer.proxyTriangleCount() << ", \"cpu_fps_proxy\": " << 1000.0 / cpuProxy
        << ", \"gpu_fps_proxy\": " << 1000.0 / gpuProxy << ", \"gpu_speedup_proxy\": " << cpuProxy / gpuProxy
        << ", \"backend\": \"" << jsonText(offscreen.context().description()) << "\"}" << std::endl;
}

}  // namespace

namespace {

// The offscreen renderer of SCULPT_GL_BACKEND (default auto) at pixel scale 1, or null with the error printed
// as the case `name`.
std::unique_ptr<OffscreenRenderer> benchRenderer(std::ostream& out, const char* name) {
    GlBackend backend = GlBackend::Auto;
    if (const char* value = std::getenv("SCULPT_GL_BACKEND")) {
        if (Status status = parseGlBackend(value, backend); !status) {
            printError(out, name, status.message);
            return nullptr;
        }
    }
    std::unique_ptr<OffscreenRenderer> offscreen;
    if (Status status = OffscreenRenderer::create(backend, offscreen); !status) {
        printError(out, name, status.message);
        return nullptr;
    }
    offscreen->renderer().setPixelScale(1.0f);
    return offscreen;
}

}  // namespace

void runGpuDragBenchmarks(std::ostream& out, bool tenMillion) {
    const std::unique_ptr<OffscreenRenderer> offscreen = benchRenderer(out, "gpu_drag");
    if (!offscreen) return;
    benchGpuDrag(out, *offscreen, "gpu_drag_1m", 1000, 1001, 10);  // 1,000,002 vertices
    if (tenMillion) benchGpuDrag(out, *offscreen, "gpu_drag_10m", 3163, 3163, 4);  // 10,001,468 vertices
}

void runRenderBenchmarks(std::ostream& out) {
    const std::unique_ptr<OffscreenRenderer> offscreen = benchRenderer(out, "render");
    if (!offscreen) return;
    benchFrames(out, *offscreen, "render_100k", 250, 201);   // 2 * 250 * 200 = 100,000 triangles
    // The interactive window on software GL renders without MSAA (llvmpipe pays 2-3x for 4 samples).
    benchFrames(out, *offscreen, "render_100k_1x", 250, 201, 1);
    benchFrames(out, *offscreen, "render_1m", 1000, 501);    // 2 * 1000 * 500 = 1,000,000 triangles
    benchFrames(out, *offscreen, "render_1m_1x", 1000, 501, 1);
    benchUploads(out, *offscreen);
    benchFullUpdate(out, *offscreen);
}

}  // namespace sculpt::render
