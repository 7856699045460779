// Offscreen contexts (OSMesa, EGL), the screenshot entry points and the camera.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <catch2/catch.hpp>

#include "gl_test_support.h"
#include "io/png_image.h"
#include "render/gl_functions.h"
#include "test_scenes.h"

using namespace sculpt;
using namespace sculpt::test;

TEST_CASE("offscreen: --gl-backend values", "[gl]") {
    render::GlBackend backend = render::GlBackend::OSMesa;
    CHECK(render::parseGlBackend("auto", backend).ok);
    CHECK(backend == render::GlBackend::Auto);
    CHECK(render::parseGlBackend("egl", backend).ok);
    CHECK(backend == render::GlBackend::Egl);
    CHECK(render::parseGlBackend("osmesa", backend).ok);
    CHECK(backend == render::GlBackend::OSMesa);
    const Status unknown = render::parseGlBackend("vulkan", backend);
    CHECK_FALSE(unknown.ok);
    CHECK_THAT(unknown.message, Catch::Contains("vulkan") && Catch::Contains("osmesa"));
    CHECK(backend == render::GlBackend::OSMesa);
    for (auto b : {render::GlBackend::Auto, render::GlBackend::OSMesa, render::GlBackend::Egl}) {
        render::GlBackend parsed = render::GlBackend::Auto;
        CHECK(render::parseGlBackend(render::glBackendName(b), parsed).ok);
        CHECK(parsed == b);
    }
}

TEST_CASE("offscreen: the test context reports its renderer", "[gl]") {
    const render::OffscreenContext& context = glTestRenderer().context();
    CHECK_FALSE(context.rendererName().empty());
    CHECK(context.backend() != render::GlBackend::Auto);
    WARN("GL tests run on: " << context.description());
}

TEST_CASE("offscreen: OSMesa and EGL draw the same picture", "[gl]") {
    const render::SceneData scene = latticeScene();
    render::ScreenshotOptions options;
    options.width = 160;
    options.height = 100;
    options.overlays.lattice = true;
    render::Rgba8Image pictures[2];
    std::string renderers[2];
    const render::GlBackend backends[2] = {render::GlBackend::OSMesa, render::GlBackend::Egl};
    for (int b = 0; b < 2; ++b) {
        std::unique_ptr<render::OffscreenRenderer> offscreen;
        const Status created = render::OffscreenRenderer::create(backends[b], offscreen);
        if (!created && backends[b] == render::GlBackend::Egl) {
            WARN("EGL unavailable here, comparison skipped: " << created.message);
            return;
        }
        INFO(created.message);
        REQUIRE(created.ok);
        renderers[b] = offscreen->context().rendererName();
        WARN(render::glBackendName(backends[b]) << ": " << offscreen->context().description());
        const Status rendered = offscreen->renderScene(scene, options, pictures[b]);
        INFO(rendered.message);
        REQUIRE(rendered.ok);
    }
    if (renderers[0] != renderers[1]) {
        WARN("different rasterizers (" << renderers[0] << " / " << renderers[1] << "): pictures not compared");
        return;
    }
    int different = 0;
    for (int y = 0; y < options.height; ++y)
        for (int x = 0; x < options.width; ++x) different += pixelDifference(pictures[0], pictures[1], x, y) > 0;
    CHECK(different == 0);
}

TEST_CASE("offscreen: one OffscreenRenderer serves several screenshots of different sizes", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    const render::SceneData scene = blobScene(3);
    for (const auto& [width, height] : {std::pair{64, 48}, std::pair{200, 120}, std::pair{64, 48}, std::pair{1, 1}}) {
        render::ScreenshotOptions options;
        options.width = width;
        options.height = height;
        render::Rgba8Image image;
        const Status status = offscreen.renderScene(scene, options, image);
        INFO(status.message);
        REQUIRE(status.ok);
        CHECK(image.width == width);
        CHECK(image.height == height);
        CHECK(image.pixels.size() == size_t(width) * size_t(height) * 4);
    }
    // Without MSAA too.
    render::ScreenshotOptions single;
    single.width = 80;
    single.height = 60;
    single.samples = 1;
    render::Rgba8Image image;
    CHECK(offscreen.renderScene(scene, single, image).ok);
}

TEST_CASE("offscreen: renderScreenshot writes a PNG, and a failure leaves the old file alone", "[gl]") {
    const std::string path = glTestOutputDir() + "/render_screenshot_test.png";
    std::remove(path.c_str());
    const render::SceneData scene = blobScene(3);
    render::ScreenshotOptions options;
    options.width = 96;
    options.height = 64;
    options.backend = render::GlBackend::OSMesa;
    options.yawDeg = -40.0f;
    options.pitchDeg = 10.0f;
    {
        const Status status = render::renderScreenshot(scene, options, path);
        INFO(status.message);
        REQUIRE(status.ok);
    }
    glTestRenderer();  // make the shared test context current again
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels;
    REQUIRE(io::readPng(path, width, height, pixels).ok);
    CHECK(width == 96);
    CHECK(height == 64);
    const auto bytes = std::filesystem::file_size(path);

    render::SceneData broken = scene;
    broken.positions(0, 0) = std::numeric_limits<double>::quiet_NaN();
    const Status failed = render::renderScreenshot(broken, options, path);
    glTestRenderer();
    CHECK_FALSE(failed.ok);
    CHECK(std::filesystem::file_size(path) == bytes);
    CHECK(io::readPng(path, width, height, pixels).ok);

    const Status badPath = render::renderScreenshot(scene, options, glTestOutputDir() + "/no/such/dir/x.png");
    glTestRenderer();
    CHECK_FALSE(badPath.ok);
    CHECK_THAT(badPath.message, Catch::Contains("no/such/dir"));
}

TEST_CASE("camera: frame fits the bounding sphere in both fields of view", "[gl]") {
    render::Bounds bounds;
    bounds.add(glm::vec3(-1.0f, -2.0f, 0.0f));
    bounds.add(glm::vec3(3.0f, 2.0f, 1.0f));
    for (float aspect : {0.5f, 1.0f, 1.6f, 3.0f}) {
        render::Camera camera;
        camera.frame(bounds, aspect, 0.8f);
        CHECK(camera.target == bounds.center());
        // Every box corner projects inside the viewport.
        const glm::mat4 viewProjection = camera.projection(aspect) * camera.view();
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p((corner & 1) ? bounds.max.x : bounds.min.x, (corner & 2) ? bounds.max.y : bounds.min.y,
                              (corner & 4) ? bounds.max.z : bounds.min.z);
            const glm::vec4 clip = viewProjection * glm::vec4(p, 1.0f);
            INFO("aspect " << aspect << " corner " << corner);
            CHECK(clip.w > 0.0f);
            CHECK(std::abs(clip.x / clip.w) < 1.0f);
            CHECK(std::abs(clip.y / clip.w) < 1.0f);
            CHECK(clip.z / clip.w > -1.0f);
            CHECK(clip.z / clip.w < 1.0f);
        }
    }
    // A tight sphere radius (from the points) frames closer than the box's half diagonal.
    const render::SceneData scene = blobScene(3);
    const render::Bounds tight = render::boundsOf(scene.positions);
    REQUIRE(tight.sphereRadius > 0.0f);
    CHECK(tight.radius() < 0.5f * glm::length(tight.max - tight.min));
    render::Bounds empty;
    render::Camera unchanged;
    unchanged.frame(empty, 1.0f);
    CHECK(unchanged.distance == render::Camera{}.distance);
}

TEST_CASE("png: writePng and readPng round-trip, and a failed write keeps the old file", "[gl]") {
    const std::string path = glTestOutputDir() + "/png_round_trip.png";
    std::vector<std::uint8_t> rgba(7 * 5 * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = std::uint8_t(i * 37 + 11);
    REQUIRE(io::writePng(path, 7, 5, rgba.data()).ok);
    int width = 0, height = 0;
    std::vector<std::uint8_t> back;
    REQUIRE(io::readPng(path, width, height, back).ok);
    CHECK(width == 7);
    CHECK(height == 5);
    CHECK(back == rgba);

    CHECK_FALSE(io::writePng(path, 0, 5, rgba.data()).ok);
    CHECK_FALSE(io::writePng(path, 7, 5, nullptr).ok);
    CHECK(io::readPng(path, width, height, back).ok);
    CHECK(back == rgba);
    const Status missingDir = io::writePng(glTestOutputDir() + "/missing_dir/x.png", 7, 5, rgba.data());
    CHECK_FALSE(missingDir.ok);
    CHECK_THAT(missingDir.message, Catch::Contains("missing_dir"));
    // No temporary files of these writes are left behind (".png_round_trip.png.tmp-<pid>-..."; other tests
    // run in parallel write their own files into this folder).
    for (const auto& entry : std::filesystem::directory_iterator(glTestOutputDir()))
        CHECK(entry.path().filename().string().find(".png_round_trip.png.tmp") == std::string::npos);

    const Status notPng = [&] {
        const std::string text = glTestOutputDir() + "/not_a_png.png";
        std::ofstream(text) << "hello";
        return io::readPng(text, width, height, back);
    }();
    CHECK_FALSE(notPng.ok);
    CHECK(back == rgba);
}
