// The decimated proxy drawn while things move (render/mesh_proxy.h): when there is one, that draw() uses it
// only when asked, and that it deforms with the mesh (it shares the mesh's vertices).
#include <catch2/catch.hpp>

#include "gl_test_support.h"
#include "render/mesh_proxy.h"
#include "test_meshes.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 320, kHeight = 200;

render::Rgba8Image drawn(render::OffscreenRenderer& offscreen, const render::Camera& camera, bool proxy) {
    render::DrawOptions options;
    options.proxy = proxy;
    render::Rgba8Image image;
    const Status status = offscreen.render(camera, options, kWidth, kHeight, 4, &image);
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

}  // namespace

TEST_CASE("mesh proxy: only large meshes get one, with fewer triangles over the same vertices", "[gl]") {
    const test::TestMesh small = test::makeUvSphere(100, 101);  // 20,000 triangles
    CHECK(render::buildMeshProxy(small.positions, small.triangles).rows() == 0);
    const test::TestMesh large = test::makeUvSphere(250, 241);  // 120,000 triangles
    const Triangles proxy = render::buildMeshProxy(large.positions, large.triangles);
    const render::MeshProxyOptions defaults;
    REQUIRE(proxy.rows() > 0);
    CHECK(proxy.rows() <= large.triangles.rows() * 3 / 4);
    CHECK(proxy.rows() >= defaults.targetTriangles / 2);
    CHECK(proxy.minCoeff() >= 0);
    CHECK(proxy.maxCoeff() < large.positions.rows());
}

TEST_CASE("mesh proxy: drawn only when asked, and it follows the deformation", "[gl]") {
    render::OffscreenRenderer& offscreen = test::glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const test::TestMesh sphere = test::makeUvSphere(250, 241);
    render::SceneData scene;
    scene.positions = sphere.positions;
    scene.triangles = sphere.triangles;
    REQUIRE(renderer.setScene(scene).ok);
    REQUIRE(renderer.proxyTriangleCount() > 0);
    REQUIRE(renderer.proxyTriangleCount() < renderer.triangleCount());
    render::ScreenshotOptions framing;
    framing.width = kWidth;
    framing.height = kHeight;
    const render::Camera camera = render::screenshotCamera(renderer.meshBounds(), renderer.latticeBounds(), framing);

    const render::Rgba8Image full = drawn(offscreen, camera, false);
    CHECK(renderer.lastDrawnTriangles() == renderer.triangleCount());
    const render::Rgba8Image proxy = drawn(offscreen, camera, true);
    CHECK(renderer.lastDrawnTriangles() == renderer.proxyTriangleCount());
    // The stand-in looks like the mesh (same silhouette within a pixel or two, same normals).
    CHECK(test::differingFraction(full, proxy) <= test::goldenMaxDifferingFraction());

    // Pull the upper half up by half the radius: the proxy draws the new shape, not the loaded one.
    Positions pulled = sphere.positions;
    std::vector<int> moved;
    for (Eigen::Index v = 0; v < pulled.rows(); ++v)
        if (pulled(v, 1) > 0.0) {
            pulled(v, 1) *= 1.5;
            moved.push_back(int(v));
        }
    REQUIRE(renderer.updatePositions(pulled, moved).ok);
    const render::Rgba8Image pulledFull = drawn(offscreen, camera, false);
    const render::Rgba8Image pulledProxy = drawn(offscreen, camera, true);
    CHECK(test::differingFraction(proxy, pulledProxy) > 0.05);  // the shape changed visibly...
    CHECK(test::differingFraction(pulledFull, pulledProxy) <= test::goldenMaxDifferingFraction());  // ...in both alike
}
