// Issue: picking in non-box lattices picks what is seen. On a frozen cylinder lattice (welded axis, pinned outer
// layer) a click on a visible free control point picked a pinned outer one drawn over or behind it, and the inner
// points could be reached only by box select. Here, from many views (random orbits, fixed seed), a click at the
// drawn position of every free marker picks a free point drawn under the cursor (within a marker's size of it),
// never a pinned one; the hint and the ring name that very point before the click. The views are chosen so that
// the old rule (nearest marker on screen, pinned or not) picks a pinned point for some of these clicks.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "app/window/lattice_commands.h"
#include "app/window/sculpt_app.h"
#include "app/window/tools.h"
#include "app/window/view_navigation.h"
#include "core/volume/lattice_net.h"
#include "render/palette.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

}  // namespace

TEST_CASE("window picking: on a cylinder lattice a click on a free marker picks a free point under the cursor, never a pinned one", "[gl][effd][picking]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    core::Session& session = state.session;
    core::LatticeNet net;
    REQUIRE(core::makeCylinderNet(Eigen::Vector3d(0, -1.0, 0), Eigen::Vector3d::UnitY(), 0.6, 2.0, {2, 3, 2}, {2, 2}, net));
    core::OpReport added;
    REQUIRE(session.tools().add({"cylinder", std::make_shared<const core::LatticeNet>(net)}, added));
    app::freezeLatticeCommand(state, 0, 0);
    INFO(state.status);
    REQUIRE(session.tools().frozen() == 0);
    sculptApp.onKey({app::Key::Tab, app::KeyAction::Press, {}}, {});
    REQUIRE(state.tools.mode == app::ToolMode::Lattice);
    const core::Lattice& lattice = session.lattice();
    const double overlap = render::kControlPointSize;
    const size_t history = session.history().size();
    std::mt19937 random(4);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int clicks = 0, oldRulePinned = 0;
    for (int view = 0; view < 12; ++view) {
        app::orbitView(state, static_cast<double>(random() % 400) - 200.0, static_cast<double>(random() % 200) - 100.0);
        const Positions points = session.cage().cagePoints();
        const std::vector<std::uint8_t> shown = app::shownControlPoints(state);
        for (int id = 0; id < lattice.controlPointCount(); ++id) {
            if (!shown[static_cast<size_t>(id)] || lattice.pinned[static_cast<size_t>(id)]) continue;
            double x = 0.0, y = 0.0;
            if (!app::projectToPixel(state.camera, kWidth, kHeight, points.row(id).transpose(), x, y)) continue;
            if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) continue;
            // A user's click on a marker lands within a few pixels of its centre.
            const double dx = 3.0 * unit(random), dy = 3.0 * unit(random);
            const double reach = std::hypot(dx, dy);
            x += dx;
            y += dy;
            const int oldRule = app::controlPointAtPixel(points, shown, state.camera, kWidth, kHeight, x, y, 9.0);
            if (oldRule >= 0 && lattice.pinned[static_cast<size_t>(oldRule)]) ++oldRulePinned;
            // Hover first: the hint names the point a click would pick.
            sculptApp.onMouseMove({x, y, {}}, {});
            const int hovered = state.tools.lattice.hovered;
            REQUIRE(hovered >= 0);
            CHECK(state.tools.hint.find(lattice.controlPointName(hovered)) != std::string::npos);
            sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
            sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, {}}, {});
            ++clicks;
            REQUIRE(state.tools.lattice.points.size() == 1);
            const int picked = state.tools.lattice.points.front();
            INFO("view " << view << ", marker " << id << " picked " << picked);
            CHECK(picked == hovered);
            CHECK_FALSE(lattice.pinned[static_cast<size_t>(picked)]);
            double px = 0.0, py = 0.0;
            REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, points.row(picked).transpose(), px, py));
            // Under the cursor: no farther than the clicked marker plus a marker's size.
            CHECK(std::hypot(px - x, py - y) <= reach + overlap + 1e-9);
            CHECK(session.history().size() == history);  // a click selects, nothing moves
        }
    }
    WARN(clicks << " clicks; the old rule picked a pinned point for " << oldRulePinned);
    CHECK(clicks > 50);
    CHECK(oldRulePinned > 0);
}
