// Properties of the renderer that need no golden image.
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "gl_test_support.h"
#include "render/gl_functions.h"
#include "render/shader_program.h"
#include "test_scenes.h"

using namespace sculpt;
using namespace sculpt::test;

namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 100;

render::Camera cameraFor(const render::Renderer& renderer) {
    render::ScreenshotOptions options;
    options.width = kWidth;
    options.height = kHeight;
    return render::screenshotCamera(renderer.meshBounds(), renderer.latticeBounds(), options);
}

render::Rgba8Image draw(render::OffscreenRenderer& offscreen, const render::Camera& camera,
                        const render::DrawOptions& options = {}) {
    render::Rgba8Image image;
    const Status status = offscreen.render(camera, options, kWidth, kHeight, 4, &image);
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

std::array<int, 4> pixel(const render::Rgba8Image& image, int x, int y) {
    const std::uint8_t* p = &image.pixels[(size_t(y) * size_t(image.width) + size_t(x)) * 4];
    return {p[0], p[1], p[2], p[3]};
}

int countDifferent(const render::Rgba8Image& a, const render::Rgba8Image& b, int tolerance) {
    int count = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) count += pixelDifference(a, b, x, y) > tolerance;
    return count;
}

void requireOk(const Status& status) {
    INFO(status.message);
    REQUIRE(status.ok);
}

}  // namespace

TEST_CASE("renderer: an empty mesh renders only the background gradient", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    requireOk(offscreen.renderer().setScene(render::SceneData{}));
    REQUIRE(offscreen.renderer().vertexCount() == 0);
    render::DrawOptions everything;
    everything.lattice = everything.wireframe = everything.jacobian = everything.affected = true;
    const render::Rgba8Image image = draw(offscreen, render::Camera{}, everything);
    for (int y = 0; y < image.height; ++y) {
        // The gradient is interpolated in sRGB from the top row's colour to the bottom row's.
        const float t = (float(y) + 0.5f) / float(image.height);
        for (int x = 0; x < image.width; ++x) {
            const auto p = pixel(image, x, y);
            for (int c = 0; c < 3; ++c) {
                const float expected = 255.0f * (render::kBackgroundTop[size_t(c)] * (1.0f - t) +
                                                 render::kBackgroundBottom[size_t(c)] * t);
                INFO("pixel (" << x << ", " << y << ") channel " << c);
                REQUIRE(std::abs(float(p[size_t(c)]) - expected) <= 1.5f);
            }
            REQUIRE(p[3] == 255);
        }
    }
}

TEST_CASE("renderer: a zero-size viewport is a clean error", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    const render::SceneData scene = blobScene(2);
    requireOk(offscreen.renderer().setScene(scene));
    render::Rgba8Image image;
    for (const auto& [width, height] : {std::pair{0, 100}, std::pair{100, 0}, std::pair{-5, 10}, std::pair{0, 0}}) {
        const Status status = offscreen.render(render::Camera{}, {}, width, height, 4, &image);
        CHECK_FALSE(status.ok);
        CHECK_THAT(status.message, Catch::Contains("empty"));
        CHECK_FALSE(offscreen.renderer().draw(render::Camera{}, {}, width, height).ok);
    }
    render::ScreenshotOptions options;
    options.width = 0;
    const Status screenshot = render::renderScreenshot(scene, options, glTestOutputDir() + "/never_written.png");
    CHECK_FALSE(screenshot.ok);
    // The renderer is still usable afterwards.
    CHECK(draw(glTestRenderer(), cameraFor(offscreen.renderer())).width == kWidth);
}

TEST_CASE("renderer: non-finite input is rejected and never reaches the screen", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const render::SceneData scene = blobScene(3);
    requireOk(renderer.setScene(scene));
    const render::Camera camera = cameraFor(renderer);
    const render::Rgba8Image before = draw(offscreen, camera);
    const double nan = std::numeric_limits<double>::quiet_NaN();

    SECTION("setMesh") {
        render::SceneData bad = scene;
        bad.positions(7, 1) = nan;
        const Status status = renderer.setMesh(bad.positions, bad.triangles);
        CHECK_FALSE(status.ok);
        CHECK_THAT(status.message, Catch::Contains("row 7") && Catch::Contains("not finite"));
        CHECK(renderer.vertexCount() == scene.positions.rows());  // previous mesh kept
    }
    SECTION("updatePositions") {
        Positions moved = scene.positions;
        moved.row(3) *= 1.5;
        moved(5, 0) = std::numeric_limits<double>::infinity();
        const Status status = renderer.updatePositions(moved, {3, 5});
        CHECK_FALSE(status.ok);
        CHECK_THAT(status.message, Catch::Contains("vertex 5"));
        CHECK(renderer.positions().row(3) == scene.positions.row(3));  // all or nothing
    }
    SECTION("lattice, constraints and fields") {
        render::LatticeView lattice = makeBoxLattice({-1, -1, -1}, {1, 1, 1}, 3, 3, 3);
        lattice.controlPoints(4, 2) = nan;
        CHECK_FALSE(renderer.setLattice(lattice).ok);
        render::ConstraintView constraints;
        constraints.sources = Positions::Zero(1, 3);
        constraints.targets = Positions::Constant(1, 3, nan);
        CHECK_FALSE(renderer.setConstraints(constraints).ok);
        std::vector<float> det(size_t(scene.positions.rows()), 1.0f);
        det[9] = std::numeric_limits<float>::quiet_NaN();
        CHECK_FALSE(renderer.setJacobianField(det).ok);
        std::vector<float> weights(size_t(scene.positions.rows()), 0.5f);
        weights[2] = std::numeric_limits<float>::quiet_NaN();
        CHECK_FALSE(renderer.setAffectedWeights(weights).ok);
    }
    SECTION("bad indices and sizes") {
        Triangles triangles = scene.triangles;
        triangles(0, 2) = int(scene.positions.rows());
        CHECK_FALSE(renderer.setMesh(scene.positions, triangles).ok);
        CHECK_FALSE(renderer.updatePositions(scene.positions, {-1}).ok);
        CHECK_FALSE(renderer.updatePositions(scene.positions.topRows(3), {0}).ok);
        CHECK_FALSE(renderer.setJacobianField(std::vector<float>(3, 1.0f)).ok);
        render::LatticeView lattice = makeBoxLattice({-1, -1, -1}, {1, 1, 1}, 3, 3, 3);
        lattice.nw = 2;  // 27 points for a 3 x 3 x 2 lattice
        CHECK_FALSE(renderer.setLattice(lattice).ok);
    }
    render::DrawOptions all;
    all.lattice = all.jacobian = all.affected = true;
    const render::Rgba8Image after = draw(offscreen, camera, all);
    CHECK(countDifferent(before, after, 0) == 0);
}

TEST_CASE("renderer: shader compile and link errors carry the driver's log", "[gl]") {
    const render::GlFunctions& gl = glTestRenderer().context().gl();
    const std::string vertex = "layout(location = ATTRIB_POSITION) in vec3 aPosition;\n"
                               "void main() { gl_Position = vec4(aPosition, 1.0); }\n";
    GLuint program = 99;
    const Status compile = render::buildProgram(gl, "broken", vertex,
                                                "out vec4 fragColor;\nvoid main() { fragColor = undefinedThing; }\n",
                                                program);
    CHECK_FALSE(compile.ok);
    CHECK(program == 0);
    CHECK_THAT(compile.message, Catch::Contains("broken.frag") && Catch::Contains("compile") &&
                                    Catch::Contains("undefinedThing"));
    // Compiles, but cannot link: the function is declared and never defined.
    const Status link = render::buildProgram(gl, "unlinkable", vertex,
                                             "vec4 undefinedHelper();\nout vec4 fragColor;\n"
                                             "void main() { fragColor = undefinedHelper(); }\n",
                                             program);
    CHECK_FALSE(link.ok);
    CHECK_THAT(link.message, Catch::Contains("unlinkable") && Catch::Contains("link"));
    CHECK_FALSE(render::buildEmbeddedProgram(gl, "no_such_program", program).ok);
    // ... while every embedded program builds.
    for (const char* name : {"background", "mesh", "line", "point"}) {
        const Status status = render::buildEmbeddedProgram(gl, name, program);
        INFO(name << ": " << status.message);
        CHECK(status.ok);
        gl.DeleteProgram(program);
    }
}

TEST_CASE("renderer: sparse position updates give the same picture as a full upload", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const render::SceneData scene = blobScene(4);
    const int vertexCount = int(scene.positions.rows());
    // A local bump: the vertices near one point move outward (about 3% of them).
    Positions moved = scene.positions;
    std::vector<int> changed;
    const Eigen::RowVector3d center = scene.positions.row(extremeVertex(scene.positions, {0.6, 0.5, 0.62}));
    for (int v = 0; v < vertexCount; ++v) {
        const double distance = (scene.positions.row(v) - center).norm();
        if (distance < 0.35) {
            moved.row(v) *= 1.0 + 0.25 * (1.0 - distance / 0.35);
            changed.push_back(v);
        }
    }
    REQUIRE(changed.size() * 10 < size_t(vertexCount));

    requireOk(renderer.setMesh(moved, scene.triangles));
    const render::Camera camera = cameraFor(renderer);
    const render::Rgba8Image full = draw(offscreen, camera);
    const Positions fullNormals = renderer.normals();

    requireOk(renderer.setMesh(scene.positions, scene.triangles));
    const render::Rgba8Image rest = draw(offscreen, camera);
    requireOk(renderer.updatePositions(moved, changed));
    const render::UploadStats upload = renderer.lastUpload();
    CHECK_FALSE(upload.fullUpload);
    CHECK(upload.verticesUploaded >= int(changed.size()));
    CHECK(upload.verticesUploaded < vertexCount / 4);
    CHECK((renderer.normals() - fullNormals).cwiseAbs().maxCoeff() < 1e-12);
    const render::Rgba8Image sparse = draw(offscreen, camera);
    CHECK(countDifferent(rest, full, 8) > 100);   // the bump is visible ...
    CHECK(countDifferent(sparse, full, 0) == 0);  // ... and identical either way

    // Many changes take the whole-buffer path, with the same result.
    requireOk(renderer.setMesh(scene.positions, scene.triangles));
    std::vector<int> all(static_cast<size_t>(vertexCount));
    for (int v = 0; v < vertexCount; ++v) all[size_t(v)] = v;
    requireOk(renderer.updatePositions(moved, all));
    CHECK(renderer.lastUpload().fullUpload);
    CHECK(countDifferent(draw(offscreen, camera), full, 0) == 0);
}

TEST_CASE("renderer: det J colours mean what they say", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const render::SceneData scene = blobScene(3);
    requireOk(renderer.setScene(scene));
    const render::Camera camera = cameraFor(renderer);
    render::DrawOptions jacobian;
    jacobian.jacobian = true;
    const auto centre = [&](float det) {
        requireOk(renderer.setJacobianField(std::vector<float>(size_t(scene.positions.rows()), det)));
        return pixel(draw(offscreen, camera, jacobian), kWidth / 2, kHeight / 2);
    };
    const auto plain = pixel(draw(offscreen, camera), kWidth / 2, kHeight / 2);
    const auto unchanged = centre(1.0f);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(unchanged[size_t(c)] - plain[size_t(c)]) <= 1);  // 1 = the clay
    const auto expanded = centre(4.0f);
    CHECK(expanded[0] > expanded[2] + 60);  // warm
    const auto contracted = centre(0.25f);
    CHECK(contracted[2] > contracted[0] + 60);  // cool
    // Symmetric on the log scale: x4 and /4 are equally far from neutral.
    const auto saturation = [](std::array<int, 4> p) { return std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}); };
    CHECK(std::abs(saturation(expanded) - saturation(contracted)) < 60);
    // Fold-over: magenta or black stripes, nothing in between except at stripe edges.
    requireOk(renderer.setJacobianField(std::vector<float>(size_t(scene.positions.rows()), -0.5f)));
    const render::Rgba8Image folded = draw(offscreen, camera, jacobian);
    int magenta = 0, black = 0;
    for (int y = kHeight / 2 - 10; y < kHeight / 2 + 10; ++y)
        for (int x = kWidth / 2 - 10; x < kWidth / 2 + 10; ++x) {
            const auto p = pixel(folded, x, y);
            magenta += p[0] > 200 && p[1] < 40 && p[2] > 200;
            black += p[0] < 40 && p[1] < 40 && p[2] < 40;
        }
    CHECK(magenta > 100);
    CHECK(black > 100);
}

TEST_CASE("renderer: the lattice and constraints never hide the mesh", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    const render::SceneData scene = latticeScene();
    // The golden size, where markers are drawn at half their 1280 x 800 size.
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.overlays.lattice = true;
    options.overlays.constraints = true;
    render::Rgba8Image overlaid, plain;
    requireOk(offscreen.renderScene(scene, options, overlaid));
    options.overlays.lattice = options.overlays.constraints = false;
    options.overlays.background = false;  // alpha 0 outside the mesh
    // Same camera: screenshotCamera frames the lattice only when it is drawn, so keep the lattice framing.
    const render::Camera camera = render::screenshotCamera(offscreen.renderer().meshBounds(),
                                                           offscreen.renderer().latticeBounds(), [&] {
                                                               render::ScreenshotOptions framing = options;
                                                               framing.overlays.lattice = true;
                                                               return framing;
                                                           }());
    requireOk(offscreen.render(camera, options.overlays, options.width, options.height, 4, &plain));
    // Over the mesh, lattice lines and points cover some pixels, but the surface stays visible: on average
    // the picture changes little and few pixels change a lot.
    long meshPixels = 0, changedSum = 0, hidden = 0;
    for (int y = 0; y < options.height; ++y)
        for (int x = 0; x < options.width; ++x) {
            if (pixel(plain, x, y)[3] < 255) continue;
            ++meshPixels;
            const int difference = pixelDifference(plain, overlaid, x, y) ;
            changedSum += difference;
            hidden += difference > 100;
        }
    REQUIRE(meshPixels > 3000);
    CHECK(double(changedSum) / double(meshPixels) < 25.0);
    CHECK(double(hidden) / double(meshPixels) < 0.06);  // markers (opaque by design) and the handle
}

TEST_CASE("renderer: vertex colours are the material where asked, the clay otherwise", "[gl]") {
    render::OffscreenRenderer& offscreen = glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const render::SceneData scene = blobScene(3);
    const int vertexCount = int(scene.positions.rows());
    requireOk(renderer.setScene(scene));
    const render::Camera camera = cameraFor(renderer);
    const render::Rgba8Image clay = draw(offscreen, camera);
    CHECK_FALSE(renderer.hasVertexColors());

    // Red over the top half of the blob, blue under it (world y is up on screen in this view).
    std::vector<float> colours(3 * size_t(vertexCount));
    const double middle = 0.5 * (scene.positions.col(1).maxCoeff() + scene.positions.col(1).minCoeff());
    for (int v = 0; v < vertexCount; ++v) {
        const bool top = scene.positions(v, 1) > middle;
        colours[3 * size_t(v)] = top ? 0.9f : 0.05f;
        colours[3 * size_t(v) + 1] = 0.05f;
        colours[3 * size_t(v) + 2] = top ? 0.05f : 0.9f;
    }
    requireOk(renderer.setVertexColors(colours));
    REQUIRE(renderer.hasVertexColors());
    const render::Rgba8Image coloured = draw(offscreen, camera);
    // Sample the lit front of each half along the centre column: the reddest and the bluest pixel.
    int redMargin = -255, blueMargin = -255;
    for (int y = 0; y < kHeight; ++y) {
        const auto p = pixel(coloured, kWidth / 2, y);
        if (y < kHeight / 2) redMargin = std::max(redMargin, p[0] - std::max(p[1], p[2]));
        else blueMargin = std::max(blueMargin, p[2] - std::max(p[0], p[1]));
    }
    CHECK(redMargin > 60);
    CHECK(blueMargin > 60);
    // The clay itself is a grey: no pixel of it is that red or that blue.
    for (int y = 0; y < kHeight; ++y) {
        const auto p = pixel(clay, kWidth / 2, y);
        CHECK(std::abs(p[0] - p[2]) < 40);
    }

    // Turned off in the draw options: exactly the clay picture.
    render::DrawOptions off;
    off.vertexColors = false;
    CHECK(countDifferent(draw(offscreen, camera, off), clay, 0) == 0);

    // A wrong count or a non-finite value is refused, and what was uploaded stays.
    const Status wrongCount = renderer.setVertexColors(std::vector<float>(3 * size_t(vertexCount) - 3, 0.5f));
    CHECK_FALSE(wrongCount.ok);
    CHECK(wrongCount.message.find("3 per vertex") != std::string::npos);
    std::vector<float> withNaN = colours;
    withNaN[3 * 7 + 1] = std::numeric_limits<float>::quiet_NaN();
    const Status nan = renderer.setVertexColors(withNaN);
    CHECK_FALSE(nan.ok);
    CHECK(nan.message.find("vertex colour 7") != std::string::npos);
    CHECK(renderer.hasVertexColors());
    CHECK(countDifferent(draw(offscreen, camera), coloured, 0) == 0);

    // A new mesh starts without them.
    requireOk(renderer.setMesh(scene.positions, scene.triangles));
    CHECK_FALSE(renderer.hasVertexColors());
    CHECK(countDifferent(draw(offscreen, camera), clay, 0) == 0);
}

TEST_CASE("renderer: a whole-mesh update of a big mesh is checked in parallel and refused whole at its first bad entry", "[gl]") {
    // Over 65536 listed vertices the checks and the copy run on every thread; the list may repeat vertices.
    render::OffscreenRenderer& offscreen = glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const render::SceneData scene = blobScene(6);  // 40962 vertices
    const int vertexCount = int(scene.positions.rows());
    requireOk(renderer.setMesh(scene.positions, scene.triangles));
    const render::Camera camera = cameraFor(renderer);
    const render::Rgba8Image rest = draw(offscreen, camera);
    Positions moved = scene.positions * 1.1;
    std::vector<int> listed;  // every vertex twice, in two interleaved passes
    for (int pass = 0; pass < 2; ++pass)
        for (int v = 0; v < vertexCount; ++v) listed.push_back(pass == 0 ? v : vertexCount - 1 - v);
    REQUIRE(listed.size() > 65536);

    std::mt19937 rng(91);
    for (int trial = 0; trial < 6; ++trial) {
        std::vector<int> bad = listed;
        Positions badPositions = moved;
        const int first = std::uniform_int_distribution<int>(0, int(listed.size()) - 2)(rng);
        const int later = std::uniform_int_distribution<int>(first + 1, int(listed.size()) - 1)(rng);
        // The first bad entry is a NaN position (odd trials) or an index out of range (even ones); a later
        // entry is bad the other way. The message names the first.
        if (trial % 2) {
            badPositions(listed[size_t(first)], 1) = std::numeric_limits<double>::quiet_NaN();
            bad[size_t(later)] = vertexCount + 5;
        } else {
            bad[size_t(first)] = -3;
            badPositions(listed[size_t(later)], 0) = std::numeric_limits<double>::infinity();
        }
        const Status status = renderer.updatePositions(badPositions, bad);
        REQUIRE_FALSE(status.ok);
        // The first bad entry in list order, found one by one (a vertex listed twice may be bad earlier).
        std::string expected;
        for (int v : bad) {
            if (v < 0 || v >= vertexCount) {
                expected = "changed vertex " + std::to_string(v) + " is outside";
                break;
            }
            if (!badPositions.row(v).allFinite()) {
                expected = "position of vertex " + std::to_string(v) + " is not finite";
                break;
            }
        }
        REQUIRE_FALSE(expected.empty());
        INFO(status.message);
        CHECK(status.message.find(expected) != std::string::npos);
        CHECK(countDifferent(draw(offscreen, camera), rest, 0) == 0);  // nothing changed
    }
    requireOk(renderer.updatePositions(moved, listed));
    CHECK(renderer.lastUpload().fullUpload);
    CHECK(renderer.positions() == moved);
    const render::Rgba8Image updated = draw(offscreen, camera);
    requireOk(renderer.setMesh(moved, scene.triangles));
    CHECK(countDifferent(draw(offscreen, camera), updated, 0) == 0);
}
