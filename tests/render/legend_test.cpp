// The det J overlay's scale and legend (render/legend.h, shaders/jacobian_colors.glsl): a moderate edit shows,
// and the legend is drawn over the picture with the overlay, in headless screenshots too.
#include <catch2/catch.hpp>

#include <algorithm>

#include "gl_test_support.h"
#include "render/bitmap_font.h"
#include "render/legend.h"
#include "render/palette.h"
#include "test_scenes.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 640, kHeight = 400;

render::Rgba8Image screenshot(const render::SceneData& scene, bool jacobian, float insetBottom = 0.0f) {
    render::ScreenshotOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.overlays.jacobian = jacobian;
    options.overlays.uiInsetBottom = insetBottom;
    render::Rgba8Image image;
    const Status status = test::glTestRenderer().renderScene(scene, options, image);
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

const std::uint8_t* at(const render::Rgba8Image& image, int x, int y) {
    return &image.pixels[(size_t(y) * size_t(image.width) + size_t(x)) * 4];
}

// Bounding box of the pixels that differ (by more than 24 in a channel) between a and b.
struct Box {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
Box differingBox(const render::Rgba8Image& a, const render::Rgba8Image& b) {
    Box box;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (test::pixelDifference(a, b, x, y) > 24) {
                box.x0 = std::min(box.x0, x);
                box.y0 = std::min(box.y0, y);
                box.x1 = std::max(box.x1, x);
                box.y1 = std::max(box.y1, y);
            }
    return box;
}

}  // namespace

TEST_CASE("legend: the numbers at the map's ends", "[gl]") {
    CHECK(render::legendNumber(2.0f, false) == "2");
    CHECK(render::legendNumber(2.0f, true) == "1/2");
    CHECK(render::legendNumber(1.5f, true) == "1/1.5");
    CHECK(render::textWidth("1/2") == 17);
    // Every character the legend writes is in the font (a missing one is a hollow box).
    const auto box = render::glyphRows('\x01');
    for (char c : std::string("det J (log scale)fold0123456789/")) CHECK(render::glyphRows(c) != box);
}

TEST_CASE("legend: drawn in the bottom-right corner with the det J overlay, above a status line", "[gl]") {
    render::SceneData scene = test::blobScene();
    scene.jacobianDet.assign(size_t(scene.positions.rows()), 1.0f);  // unchanged: the surface looks plain
    const render::Rgba8Image plain = screenshot(scene, false);
    const render::Rgba8Image withLegend = screenshot(scene, true);
    const Box box = differingBox(plain, withLegend);
    INFO("legend box " << box.x0 << "," << box.y0 << " - " << box.x1 << "," << box.y1);
    REQUIRE(box.x1 >= 0);
    CHECK(box.x0 > kWidth / 2);
    CHECK(box.y0 > kHeight / 2);
    CHECK(box.x1 < kWidth);
    CHECK(box.y1 >= kHeight - 20);
    // The bar runs from the contraction blue to the expansion red (the surface's own colours).
    const int barY = box.y0 + (box.y1 - box.y0) / 2;
    const std::uint8_t* blue = nullptr;
    const std::uint8_t* red = nullptr;
    for (int x = box.x0; x <= box.x1; ++x) {
        const std::uint8_t* p = at(withLegend, x, barY);
        if (!blue && p[2] > p[0] + 80) blue = p;
        if (p[0] > p[2] + 80) red = p;
    }
    CHECK(blue != nullptr);
    CHECK(red != nullptr);
    // With a status line drawn over the bottom 40 pixels, the legend moves up above it.
    const Box raised = differingBox(plain, screenshot(scene, true, 40.0f));
    CHECK(raised.y1 < kHeight - 40);
    CHECK(raised.y1 >= kHeight - 60);
}

TEST_CASE("legend: a moderate edit shows clearly in the det J colours", "[gl]") {
    render::SceneData scene = test::blobScene();
    scene.jacobianDet.assign(size_t(scene.positions.rows()), 1.0f);
    const render::Rgba8Image unchanged = screenshot(scene, true);
    scene.jacobianDet.assign(size_t(scene.positions.rows()), 1.25f);  // 25% more volume
    const render::Rgba8Image expanded = screenshot(scene, true);
    scene.jacobianDet.assign(size_t(scene.positions.rows()), 0.8f);
    const render::Rgba8Image contracted = screenshot(scene, true);
    // The centre of the view, on the surface: clearly redder, clearly bluer (the old 1/4 .. 4 scale moved
    // these by about 20 levels, at the golden tolerance).
    const std::uint8_t* neutral = at(unchanged, kWidth / 2, kHeight / 2);
    const std::uint8_t* red = at(expanded, kWidth / 2, kHeight / 2);
    const std::uint8_t* blue = at(contracted, kWidth / 2, kHeight / 2);
    INFO("neutral " << int(neutral[0]) << " " << int(neutral[1]) << " " << int(neutral[2]) << ", expanded " << int(red[0])
                    << " " << int(red[1]) << " " << int(red[2]) << ", contracted " << int(blue[0]) << " "
                    << int(blue[1]) << " " << int(blue[2]));
    CHECK(int(neutral[1]) - int(red[1]) > 40);  // green and blue drop toward the red
    CHECK(int(neutral[0]) - int(blue[0]) > 40);  // red drops toward the blue
}
