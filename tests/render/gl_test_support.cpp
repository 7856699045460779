#include "gl_test_support.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include <catch2/catch.hpp>

#include "io/png_image.h"

namespace sculpt::test {

namespace {

// Golden thresholds. The goldens are rendered by Mesa llvmpipe (OSMesa or EGL: same rasterizer, identical
// pixels), where a rerun is bit-exact. The slack is for other rasterizers and Mesa/LLVM versions:
//  - kChannelTolerance: a pixel counts as different only if some channel is off by more than 24/255.
//    Shading math (pow, normalize, log in the det J map) may differ by a few units between drivers;
//    24 sits well above that and well below any change of meaning (a colour-map step, a missing light).
//  - kMaxDifferentFraction: up to 1% of pixels may differ by more. With 4x MSAA, silhouette and edge pixels
//    depend on the sample pattern (llvmpipe uses the standard D3D positions, GPUs may not); at 320x200
//    the silhouettes and lattice/wire lines are roughly 3-6% of the picture, so a different pattern
//    moves a fraction of them. A moved, missing or recoloured object changes far more than 1%.
constexpr int kChannelTolerance = 24;
constexpr double kMaxDifferentFraction = 0.01;

bool updateRequested() {
    const char* value = std::getenv("SCULPT_UPDATE_GOLDEN");
    return value && std::string(value) == "1";
}

render::GlBackend testBackend() {
    render::GlBackend backend = render::GlBackend::OSMesa;
    if (const char* value = std::getenv("SCULPT_GL_BACKEND")) {
        const Status status = render::parseGlBackend(value, backend);
        INFO("SCULPT_GL_BACKEND: " << status.message);
        REQUIRE(status.ok);
    }
    return backend;
}

}  // namespace

render::OffscreenRenderer& glTestRenderer() {
    // note: one object made by create(), so its construction completes after OSMesa registered its own exit
    // handler (on its first context) and it is destroyed before that handler frees OSMesa's state. A static
    // unique_ptr constructed before create() was destroyed after it: a use after free at exit, whenever no
    // OSMesa context had been made before this one (a run starting with the EGL window tests).
    struct Created {
        std::unique_ptr<render::OffscreenRenderer> renderer;
        Status status = Status::success();
    };
    static Created created = [] {
        Created c;
        c.status = render::OffscreenRenderer::create(testBackend(), c.renderer);
        return c;
    }();
    INFO("creating the offscreen GL renderer: " << created.status.message);
    REQUIRE(created.status.ok);
    render::OffscreenRenderer* renderer = created.renderer.get();
    const Status current = renderer->makeCurrent();
    INFO(current.message);
    REQUIRE(current.ok);
    return *renderer;
}

std::string glTestOutputDir() {
    const std::string dir = SCULPT_GL_TEST_OUTPUT_DIR;
    std::error_code ignored;
    std::filesystem::create_directories(dir, ignored);
    return dir;
}

int pixelDifference(const render::Rgba8Image& a, const render::Rgba8Image& b, int x, int y) {
    if (a.width != b.width || a.height != b.height) return 255;
    const size_t at = (size_t(y) * size_t(a.width) + size_t(x)) * 4;
    int difference = 0;
    for (int c = 0; c < 4; ++c) difference = std::max(difference, std::abs(int(a.pixels[at + c]) - int(b.pixels[at + c])));
    return difference;
}

double differingFraction(const render::Rgba8Image& a, const render::Rgba8Image& b,
                         const std::vector<std::uint8_t>& ignore) {
    if (a.width != b.width || a.height != b.height) return 1.0;
    long counted = 0, differing = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (!ignore.empty() && ignore[size_t(y) * size_t(a.width) + size_t(x)]) continue;
            ++counted;
            differing += pixelDifference(a, b, x, y) > kChannelTolerance;
        }
    return counted > 0 ? double(differing) / double(counted) : 0.0;
}

double goldenMaxDifferingFraction() { return kMaxDifferentFraction; }

void checkGolden(const render::Rgba8Image& actual, const std::string& name) {
    const std::string goldenPath = std::string(SCULPT_SOURCE_DIR) + "/tests/golden/" + name + ".png";
    if (updateRequested()) {
        const Status written = io::writePng(goldenPath, actual.width, actual.height, actual.pixels.data());
        INFO(written.message);
        REQUIRE(written.ok);
        WARN("SCULPT_UPDATE_GOLDEN=1: wrote " << goldenPath);
        return;
    }
    render::Rgba8Image golden;
    const Status read = io::readPng(goldenPath, golden.width, golden.height, golden.pixels);
    const std::string actualPath = glTestOutputDir() + "/" + name + "_actual.png";
    if (!read) {
        io::writePng(actualPath, actual.width, actual.height, actual.pixels.data());
        FAIL("no golden image: " << read.message << "\nthe picture rendered now is " << actualPath
                                 << "\n(to create the golden: SCULPT_UPDATE_GOLDEN=1 ./gl_tests)");
    }
    REQUIRE(golden.width == actual.width);
    REQUIRE(golden.height == actual.height);

    // Diff image: the golden, dimmed and greyed, with every differing pixel in red (brighter = larger).
    render::Rgba8Image diff{actual.width, actual.height, std::vector<std::uint8_t>(actual.pixels.size())};
    long differing = 0;
    int largest = 0;
    for (int y = 0; y < actual.height; ++y)
        for (int x = 0; x < actual.width; ++x) {
            const int difference = pixelDifference(actual, golden, x, y);
            largest = std::max(largest, difference);
            std::uint8_t* out = &diff.pixels[(size_t(y) * size_t(actual.width) + size_t(x)) * 4];
            const std::uint8_t* in = &golden.pixels[(size_t(y) * size_t(actual.width) + size_t(x)) * 4];
            if (difference > kChannelTolerance) {
                ++differing;
                out[0] = std::uint8_t(std::min(255, 128 + difference));
                out[1] = out[2] = 0;
            } else {
                const std::uint8_t grey = std::uint8_t((int(in[0]) + int(in[1]) + int(in[2])) / 9);
                out[0] = out[1] = out[2] = grey;
            }
            out[3] = 255;
        }
    const double fraction = double(differing) / (double(actual.width) * actual.height);
    if (fraction > kMaxDifferentFraction) {
        const std::string diffPath = glTestOutputDir() + "/" + name + "_diff.png";
        io::writePng(actualPath, actual.width, actual.height, actual.pixels.data());
        io::writePng(diffPath, diff.width, diff.height, diff.pixels.data());
        FAIL("'" << name << "' differs from " << goldenPath << ": " << differing << " pixels (" << 100.0 * fraction
                 << "%, allowed " << 100.0 * kMaxDifferentFraction << "%) differ by more than " << kChannelTolerance
                 << "/255 (largest " << largest << ")\n  actual: " << actualPath << "\n  diff:   " << diffPath);
    }
}

}  // namespace sculpt::test
