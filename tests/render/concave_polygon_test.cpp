// A concave OBJ face on screen: the handed-over U (tests/io/data/cases/concave_u.obj, one 8-corner face,
// 3 x 3 with a 1 x 2 notch open at the top) seen looking down -z. The notch must show the background, the
// U's arms the mesh, and picking must agree (the renderer and picking use the same triangles).
#include <array>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "app/window/picking.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/png_image.h"
#include "render/offscreen_renderer.h"

using namespace sculpt;
using namespace sculpt::test;

namespace {

constexpr int kSize = 240;

// The pixel (column, row from the top) where a world point lands.
std::array<int, 2> pixelOf(const render::Camera& camera, const Eigen::Vector3d& point) {
    const glm::vec4 clip = camera.projection(1.0f) * camera.view() * glm::vec4(glm::vec3(point.x(), point.y(), point.z()), 1.0f);
    const float x = (clip.x / clip.w * 0.5f + 0.5f) * float(kSize);
    const float y = (1.0f - (clip.y / clip.w * 0.5f + 0.5f)) * float(kSize);
    return {int(x), int(y)};
}

const std::uint8_t* pixel(const render::Rgba8Image& image, std::array<int, 2> at) {
    return &image.pixels[(size_t(at[1]) * size_t(image.width) + size_t(at[0])) * 4];
}

}  // namespace

TEST_CASE("concave polygon: the notch of the U shows the background, looking down -z", "[gl]") {
    io::ObjMesh mesh;
    const Status loaded = io::loadObj(std::string(SCULPT_SOURCE_DIR) + "/tests/io/data/cases/concave_u.obj", mesh);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    REQUIRE(mesh.faceCount() == 1);
    render::SceneData scene;
    scene.positions = mesh.positions;
    scene.triangles = mesh.triangles;

    render::OffscreenRenderer& offscreen = glTestRenderer();
    render::ScreenshotOptions options;
    options.width = options.height = kSize;
    options.yawDeg = 0.0f;  // eye on +z, looking down -z
    options.pitchDeg = 0.0f;
    render::Rgba8Image picture, mask, background;
    REQUIRE(offscreen.renderScene(scene, options, picture).ok);
    const Status written = io::writePng(glTestOutputDir() + "/concave_u.png", kSize, kSize, picture.pixels.data());
    INFO(written.message);
    REQUIRE(written.ok);
    const render::Camera camera =
        render::screenshotCamera(offscreen.renderer().meshBounds(), offscreen.renderer().latticeBounds(), options);
    // The same view without the background (alpha 0 where no triangle is) and without the mesh.
    render::DrawOptions transparent = options.overlays;
    transparent.background = false;
    REQUIRE(offscreen.render(camera, transparent, kSize, kSize, 4, &mask).ok);
    REQUIRE(offscreen.renderer().setScene(render::SceneData{}).ok);
    REQUIRE(offscreen.render(camera, options.overlays, kSize, kSize, 4, &background).ok);

    // Sample a grid over the notch (1 < x < 2, 1 < y < 3, kept a margin from its edges) and over the arms
    // and the base: background in the notch, mesh elsewhere, and picking the same.
    int notchSamples = 0, meshSamples = 0;
    for (double y = 0.15; y < 2.9; y += 0.1)
        for (double x = 0.15; x < 2.9; x += 0.1) {
            const bool nearEdge = std::abs(x - 1.0) < 0.15 || std::abs(x - 2.0) < 0.15 || std::abs(y - 1.0) < 0.15;
            if (nearEdge) continue;
            const bool inNotch = x > 1.0 && x < 2.0 && y > 1.0;
            const Eigen::Vector3d point(x, y, 0.0);
            const std::array<int, 2> at = pixelOf(camera, point);
            REQUIRE(at[0] >= 0);
            REQUIRE(at[0] < kSize);
            REQUIRE(at[1] >= 0);
            REQUIRE(at[1] < kSize);
            INFO("point (" << x << ", " << y << ") at pixel " << at[0] << ", " << at[1]);
            app::Ray ray;
            ray.origin = Eigen::Vector3d(x, y, 5.0);
            ray.direction = Eigen::Vector3d(0.0, 0.0, -1.0);
            const app::SurfaceHit hit = app::intersectMesh(ray, mesh.positions, mesh.triangles);
            if (inNotch) {
                ++notchSamples;
                CHECK(int(pixel(mask, at)[3]) == 0);
                CHECK(pixelDifference(picture, background, at[0], at[1]) <= 2);
                CHECK(hit.triangle < 0);
            } else {
                ++meshSamples;
                CHECK(int(pixel(mask, at)[3]) == 255);
                CHECK(pixelDifference(picture, background, at[0], at[1]) > 30);
                CHECK(hit.triangle >= 0);
            }
        }
    REQUIRE(notchSamples > 50);
    REQUIRE(meshSamples > 300);
}
