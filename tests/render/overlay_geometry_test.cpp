#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "render/overlay_geometry.h"
#include "render/palette.h"
#include "test_meshes.h"

using namespace sculpt;

TEST_CASE("overlay geometry: lattice edges join exactly the grid neighbours", "[gl]") {
    for (const auto& [nu, nv, nw] : {std::tuple{1, 1, 1}, std::tuple{2, 3, 4}, std::tuple{5, 1, 2}}) {
        render::LatticeView lattice = test::makeBoxLattice({-1, -1, -1}, {1, 2, 3}, nu, nv, nw);
        std::vector<float> edges, markers;
        render::Bounds bounds;
        REQUIRE(render::buildLatticeInstances(lattice, {}, edges, markers, bounds).ok);
        const size_t expectedEdges = size_t((nu - 1) * nv * nw + nu * (nv - 1) * nw + nu * nv * (nw - 1));
        CHECK(edges.size() == expectedEdges * render::kLineFloats);
        CHECK(markers.size() == size_t(nu * nv * nw) * render::kMarkerFloats);
        for (size_t e = 0; e < expectedEdges; ++e) {
            const float* segment = &edges[e * render::kLineFloats];
            // Neighbours differ in exactly one coordinate.
            int differing = 0;
            for (int c = 0; c < 3; ++c) differing += segment[c] != segment[3 + c];
            CHECK(differing == 1);
        }
        if (nu > 1 && nv > 1 && nw > 1) {  // (a dimension of 1 sits in the middle of the box)
            CHECK(bounds.min == glm::dvec3(-1, -1, -1));
            CHECK(bounds.max == glm::dvec3(1, 2, 3));
        }
    }
}

TEST_CASE("overlay geometry: selected markers come last, pinned ones are squares", "[gl]") {
    render::LatticeView lattice = test::makeBoxLattice({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
    lattice.selected.assign(8, 0);
    lattice.pinned.assign(8, 0);
    lattice.selected[0] = 1;
    lattice.pinned[0] = 1;  // selected and pinned: a yellow square
    lattice.pinned[5] = 1;
    std::vector<float> edges, markers;
    render::Bounds bounds;
    REQUIRE(render::buildLatticeInstances(lattice, {}, edges, markers, bounds).ok);
    const auto marker = [&](int m) { return &markers[size_t(m) * render::kMarkerFloats]; };
    CHECK(marker(7)[3] == render::kSelectedPointColor.r);
    CHECK(marker(7)[5] == render::kSelectedPointColor.b);
    CHECK(marker(7)[8] == 1.0f);  // square
    CHECK(marker(6)[5] == render::kPinnedPointColor.b);
    CHECK(marker(6)[8] == 1.0f);
    for (int m = 0; m < 6; ++m) CHECK(marker(m)[8] == 0.0f);  // discs

    lattice.selected.resize(3);
    const std::vector<float> before = edges;
    CHECK_FALSE(render::buildLatticeInstances(lattice, {}, edges, markers, bounds).ok);
    CHECK(edges == before);  // unchanged on failure
    render::LatticeView empty;
    REQUIRE(render::buildLatticeInstances(empty, {}, edges, markers, bounds).ok);
    CHECK(edges.empty());
    CHECK(bounds.empty);
}

TEST_CASE("overlay geometry: constraints give a red-to-blue segment and two handles each", "[gl]") {
    render::ConstraintView constraints;
    constraints.sources = Positions::Random(3, 3);
    constraints.targets = Positions::Random(3, 3);
    std::vector<float> segments, markers;
    REQUIRE(render::buildConstraintInstances(constraints, {}, segments, markers).ok);
    CHECK(segments.size() == 3 * size_t(render::kLineFloats));
    CHECK(markers.size() == 6 * size_t(render::kMarkerFloats));
    CHECK(segments[6] == render::kSourceColor.r);
    CHECK(segments[12] == render::kTargetColor.b);
    constraints.targets = Positions::Random(2, 3);
    CHECK_FALSE(render::buildConstraintInstances(constraints, {}, segments, markers).ok);
}

TEST_CASE("overlay geometry: the brush outline is drawn as closed loops of outlineLoop points each (the circle and its mirror images)", "[gl]") {
    std::mt19937 rng(17);
    for (int trial = 0; trial < 20; ++trial) {
        const int loops = std::uniform_int_distribution<int>(1, 4)(rng), loop = std::uniform_int_distribution<int>(3, 40)(rng);
        render::ConstraintView constraints;
        constraints.outline = Positions::Random(loops * loop, 3);
        constraints.outlineLoop = trial == 0 ? 0 : loop;  // 0: one loop of every point
        const int perLoop = trial == 0 ? loops * loop : loop;
        std::vector<float> segments, markers;
        REQUIRE(render::buildConstraintInstances(constraints, {}, segments, markers).ok);
        REQUIRE(segments.size() == size_t(loops * loop) * size_t(render::kLineFloats));
        for (int c = 0; c < loops * loop; ++c) {
            const float* segment = segments.data() + size_t(c) * render::kLineFloats;
            const int next = c - c % perLoop + (c % perLoop + 1) % perLoop;  // round its own loop, never to another
            for (int k = 0; k < 3; ++k) {
                CHECK(segment[k] == float(constraints.outline(c, k)));
                CHECK(segment[3 + k] == float(constraints.outline(next, k)));
            }
            CHECK(segment[6] == render::kBrushOutlineColor.r);
        }
        if (loops * loop % (loop + 1) != 0) {
            constraints.outlineLoop = loop + 1;  // not a whole number of loops: refused
            CHECK_FALSE(render::buildConstraintInstances(constraints, {}, segments, markers).ok);
        }
    }
}

TEST_CASE("overlay geometry: placed handles are red discs and surface pins green squares, no segments", "[gl]") {
    std::mt19937 rng(91);
    for (int trial = 0; trial < 20; ++trial) {
        render::ConstraintView constraints;
        const int handles = std::uniform_int_distribution<int>(0, 6)(rng), pins = std::uniform_int_distribution<int>(0, 6)(rng);
        constraints.handles = Positions::Random(handles, 3);
        constraints.pins = Positions::Random(pins, 3);
        std::vector<float> segments, markers;
        REQUIRE(render::buildConstraintInstances(constraints, {}, segments, markers).ok);
        CHECK(segments.empty());
        REQUIRE(markers.size() == size_t(handles + pins) * size_t(render::kMarkerFloats));
        for (int m = 0; m < handles + pins; ++m) {
            const float* marker = markers.data() + size_t(m) * render::kMarkerFloats;
            const render::Rgba expected = m < handles ? render::kSourceColor : render::kSurfacePinColor;
            CHECK(marker[3] == expected.r);
            CHECK(marker[5] == expected.b);
            CHECK(marker[8] == (m < handles ? 0.0f : 1.0f));
        }
        if (pins > 0) {
            constraints.pins(0, 1) = std::nan("");
            CHECK_FALSE(render::buildConstraintInstances(constraints, {}, segments, markers).ok);
        }
    }
}

TEST_CASE("overlay geometry: the outer cage keeps the outer faces' points and edges and every selected point", "[gl]") {
    for (const auto& [nu, nv, nw] : {std::tuple{4, 4, 4}, std::tuple{5, 3, 4}, std::tuple{2, 2, 2}, std::tuple{6, 1, 3}}) {
        render::LatticeView lattice = test::makeBoxLattice({-1, -1, -1}, {1, 1, 1}, nu, nv, nw);
        const int count = nu * nv * nw;
        lattice.selected.assign(size_t(count), 0);
        lattice.outerOnly = true;
        const int interior = std::max(nu - 2, 0) * std::max(nv - 2, 0) * std::max(nw - 2, 0);
        std::vector<float> edges, markers;
        render::Bounds bounds;
        REQUIRE(render::buildLatticeInstances(lattice, {}, edges, markers, bounds).ok);
        CHECK(markers.size() == size_t(count - interior) * render::kMarkerFloats);
        // Edges along each axis: all of them minus those whose two other coordinates are both inside.
        const auto inside = [](int n) { return std::max(n - 2, 0); };
        const size_t expectedEdges = size_t((nu - 1) * (nv * nw - inside(nv) * inside(nw)) +
                                            (nv - 1) * (nu * nw - inside(nu) * inside(nw)) +
                                            (nw - 1) * (nu * nv - inside(nu) * inside(nv)));
        CHECK(edges.size() == expectedEdges * render::kLineFloats);
        for (size_t e = 0; e < expectedEdges && nu > 1 && nv > 1 && nw > 1; ++e) {
            // Each kept edge lies on a face of the box: some coordinate is at +-1 at both its ends. (A
            // dimension of 1 sits in the middle of the box.)
            const float* segment = &edges[e * render::kLineFloats];
            bool onFace = false;
            for (int c = 0; c < 3; ++c)
                onFace |= std::abs(segment[c]) == 1.0f && segment[c] == segment[3 + c];
            CHECK(onFace);
        }
        if (interior > 0) {
            lattice.selected[size_t(1 + nu * (1 + nv * 1))] = 1;  // (1, 1, 1): inside, but selected
            REQUIRE(render::buildLatticeInstances(lattice, {}, edges, markers, bounds).ok);
            CHECK(markers.size() == size_t(count - interior + 1) * render::kMarkerFloats);
            CHECK(markers[markers.size() - render::kMarkerFloats + 3] == render::kSelectedPointColor.r);
        }
    }
}

TEST_CASE("overlay geometry: a net lattice draws its net edges, its curves and only the points flagged drawn", "[gl]") {
    // A 2 x 2 x 2 "net" whose points 1 and 3 are copies (welded onto 0 and 2) and one curve of 4 samples.
    render::LatticeView lattice = test::makeBoxLattice({-1, -1, -1}, {1, 1, 1}, 2, 2, 2);
    lattice.drawn = {1, 0, 1, 0, 1, 1, 1, 1};
    lattice.netEdges = {{0, 2}, {0, 4}, {2, 6}, {4, 5}, {4, 6}, {5, 7}, {6, 7}, {1, 3}};  // the last joins copies
    Positions curve(4, 3);
    curve << 0, 0, 0, 1, 0, 0, 1, 1, 0, 2, 2, 2;
    lattice.curves = {curve};
    lattice.toolCurves = {curve};
    lattice.selected.assign(8, 0);
    lattice.selected[1] = 1;  // a selected copy is still not drawn
    std::vector<float> edges, markers;
    render::Bounds bounds;
    REQUIRE(render::buildLatticeInstances(lattice, {}, edges, markers, bounds).ok);
    CHECK(edges.size() == size_t(7 + 3 + 3) * render::kLineFloats);  // net edges between drawn points, 2 x 3 segments
    CHECK(markers.size() == size_t(6) * render::kMarkerFloats);
    CHECK(bounds.max == glm::dvec3(2, 2, 2));  // the curves count
    // The curve segments come after the net edges, in the curve colour, then the dim tool curves.
    CHECK(edges[7 * render::kLineFloats + 6] == Approx(render::kLatticeCurveColor.r));
    CHECK(edges[10 * render::kLineFloats + 6] == Approx(render::kLatticeToolColor.r));
    // Bad input fails and names it.
    render::LatticeView bad = lattice;
    bad.netEdges.push_back({0, 8});
    CHECK_FALSE(render::buildLatticeInstances(bad, {}, edges, markers, bounds).ok);
    bad = lattice;
    bad.drawn.pop_back();
    CHECK_FALSE(render::buildLatticeInstances(bad, {}, edges, markers, bounds).ok);
    bad = lattice;
    bad.curves[0](1, 1) = NAN;
    CHECK_FALSE(render::buildLatticeInstances(bad, {}, edges, markers, bounds).ok);
    // Tool curves alone (no control points) are drawn too.
    render::LatticeView tools;
    tools.toolCurves = {curve};
    REQUIRE(render::buildLatticeInstances(tools, {}, edges, markers, bounds).ok);
    CHECK(edges.size() == size_t(3) * render::kLineFloats);
    CHECK(markers.empty());
}

TEST_CASE("overlay geometry: markers shrink only where they crowd on screen", "[gl]") {
    constexpr float d = render::kControlPointSize;
    // A square grid of n x n markers `spacing` diameters apart, each drawn `copies` times at the same pixel.
    const auto grid = [&](int n, float spacing, int copies) {
        std::vector<glm::vec2> pixels;
        for (int c = 0; c < copies; ++c)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) pixels.emplace_back(100.0f + i * spacing * d, 50.0f + j * spacing * d);
        return pixels;
    };
    // Three diameters apart or more: no other marker within two diameters of any.
    CHECK(render::crowdedMarkerScale(grid(8, 5.0f, 1), d) == 1.0f);
    CHECK(render::crowdedMarkerScale(grid(8, 3.0f, 1), d) == 1.0f);
    // Two apart: an inner marker has 8 of the 24 cells around it filled, one on the border 5, a corner 3; for
    // 12 x 12 the mean is (a^2 - 1) / 24 with a = 34/12 neighbours per axis (itself included). Shrunk so their
    // area falls back to the limit's share.
    const double a = 34.0 / 12.0, crowding = (a * a - 1.0) / 24.0;
    const float spaced = render::crowdedMarkerScale(grid(12, 2.0f, 1), d);
    CHECK(spaced == Approx(std::sqrt(render::kCrowdedMarkerShare / crowding)));
    CHECK(spaced > render::kMinCrowdedMarkerScale);
    // Packed edge to edge: as small as they get, never smaller.
    CHECK(render::crowdedMarkerScale(grid(20, 1.0f, 1), d) == render::kMinCrowdedMarkerScale);
    const float heap = render::crowdedMarkerScale(grid(20, 0.2f, 1), d);
    CHECK(heap < 1.0f);
    CHECK(heap >= render::kMinCrowdedMarkerScale);
    // Markers drawn over each other (a grid seen along an axis) crowd no more than one of them.
    CHECK(render::crowdedMarkerScale(grid(8, 5.0f, 6), d) == 1.0f);
    // A dense core inside a sparse ring (a ball's poles and axis seen from afar): crowded where most markers
    // are, however much empty space the ring spans.
    std::vector<glm::vec2> ball = grid(6, 1.0f, 1);
    for (int k = 0; k < 40; ++k) {
        const float angle = 2.0f * 3.14159265f * static_cast<float>(k) / 40.0f;
        ball.emplace_back(110.0f + 100.0f * std::cos(angle), 60.0f + 100.0f * std::sin(angle));
    }
    CHECK(render::crowdedMarkerScale(ball, d) < 0.8f);
    // Nothing to crowd.
    CHECK(render::crowdedMarkerScale({}, d) == 1.0f);
    CHECK(render::crowdedMarkerScale({glm::vec2(3.0f, 4.0f)}, d) == 1.0f);
}
