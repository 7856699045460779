// Golden-image tests: small deterministic scenes compared with tests/golden/*.png (thresholds and the
// regenerate command: gl_test_support.cpp / SCULPT_UPDATE_GOLDEN=1).
#include <catch2/catch.hpp>

#include "gl_test_support.h"
#include "io/png_image.h"
#include "test_scenes.h"

using namespace sculpt;
using namespace sculpt::test;

namespace {

// Small, so llvmpipe renders each in a few milliseconds; 4x MSAA as in real screenshots.
constexpr int kGoldenWidth = 320;
constexpr int kGoldenHeight = 200;

render::Rgba8Image renderGolden(const render::SceneData& scene, const render::DrawOptions& overlays,
                                int width = kGoldenWidth, int height = kGoldenHeight) {
    render::ScreenshotOptions options;
    options.width = width;
    options.height = height;
    options.overlays = overlays;
    render::Rgba8Image image;
    const Status status = glTestRenderer().renderScene(scene, options, image);
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

render::DrawOptions overlays(bool lattice, bool wireframe, bool jacobian, bool affected) {
    render::DrawOptions options;
    options.lattice = lattice;
    options.wireframe = wireframe;
    options.jacobian = jacobian;
    options.affected = affected;
    return options;
}

}  // namespace

TEST_CASE("golden: the default mesh, shaded", "[gl][golden]") {
    if (haveDefaultMesh()) {
        Status loaded;
        const render::SceneData scene = defaultMeshScene(loaded);
        INFO(loaded.message);
        REQUIRE(loaded.ok);
        checkGolden(renderGolden(scene, overlays(false, false, false, false)), "default_mesh");
    } else {
        WARN("assets/default.obj not there yet: checking the blob instead");
    }
    checkGolden(renderGolden(blobScene(), overlays(false, false, false, false)), "blob_shaded");
}

TEST_CASE("golden: lattice with pinned and selected control points and a constraint", "[gl][golden]") {
    checkGolden(renderGolden(latticeScene(), overlays(true, false, false, false)), "lattice");
}

TEST_CASE("golden: det J overlay with contraction, expansion and fold-over", "[gl][golden]") {
    checkGolden(renderGolden(jacobianScene(), overlays(false, false, true, false)), "jacobian");
}

TEST_CASE("golden: wireframe overlay", "[gl][golden]") {
    checkGolden(renderGolden(wireframeScene(), overlays(false, true, false, false)), "wireframe");
}

TEST_CASE("golden: affected-region overlay", "[gl][golden]") {
    checkGolden(renderGolden(affectedScene(), overlays(false, false, false, true)), "affected");
}

// Not a check: renders every golden scene at 1280 x 800 into the test output folder, for looking at.
// Run with: ./gl_tests "[showcase]"
TEST_CASE("showcase: golden scenes at screenshot size", "[gl][.showcase]") {
    const std::string dir = glTestOutputDir();
    const auto save = [&](const render::Rgba8Image& image, const std::string& name) {
        const Status written = io::writePng(dir + "/" + name + ".png", image.width, image.height, image.pixels.data());
        INFO(written.message);
        REQUIRE(written.ok);
    };
    save(renderGolden(blobScene(), overlays(false, false, false, false), 1280, 800), "showcase_blob");
    if (haveDefaultMesh()) {
        Status loaded;
        render::SceneData scene = defaultMeshScene(loaded);
        REQUIRE(loaded.ok);
        save(renderGolden(scene, overlays(false, false, false, false), 1280, 800), "showcase_default_mesh");
        save(renderGolden(scene, overlays(false, true, false, false), 1280, 800), "showcase_default_mesh_wireframe");
    }
    save(renderGolden(latticeScene(), overlays(true, false, false, false), 1280, 800), "showcase_lattice");
    save(renderGolden(jacobianScene(), overlays(false, false, true, false), 1280, 800), "showcase_jacobian");
    save(renderGolden(wireframeScene(), overlays(false, true, false, false), 1280, 800), "showcase_wireframe");
    save(renderGolden(affectedScene(), overlays(false, false, false, true), 1280, 800), "showcase_affected");
    render::SceneData everything = latticeScene();
    everything.jacobianDet = jacobianScene().jacobianDet;
    everything.affectedWeight = affectedScene().affectedWeight;
    save(renderGolden(everything, overlays(true, true, true, true), 1280, 800), "showcase_everything");
    WARN("wrote showcase_*.png to " << dir);
}
