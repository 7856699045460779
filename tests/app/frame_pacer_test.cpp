// When the window draws (app/frame_pacer.h): a random stream of events, app needs and frames, checked against
// the rule stated in the header, computed here independently: the frame after an event and the two after it
// are drawn at once; then the loop waits for at most the shortest time something needs, a measurement's
// deadline included, and with no need sleeps until the next event.
#include <random>

#include <catch2/catch.hpp>

#include "app/frame_pacer.h"

using sculpt::app::FrameNeeds;
using sculpt::app::FramePacer;

TEST_CASE("frame pacer: a window with nothing happening sleeps", "[app][frame_pacer]") {
    FramePacer pacer;
    // The window's first frames are drawn without an event, then it sleeps.
    for (int f = 0; f < FramePacer::kSettleFrames; ++f) {
        CHECK(pacer.plan({}).wait == FramePacer::Wait::Poll);
        pacer.frameDrawn();
    }
    for (int f = 0; f < 10; ++f) CHECK(pacer.plan({}).wait == FramePacer::Wait::Forever);
    CHECK(pacer.framesDrawn() == FramePacer::kSettleFrames);
    CHECK_FALSE(pacer.settling());
}

TEST_CASE("frame pacer: events, needs and deadlines over random streams", "[app][frame_pacer]") {
    std::mt19937 random(30);
    for (int stream = 0; stream < 200; ++stream) {
        FramePacer pacer;
        int owed = FramePacer::kSettleFrames;  // the model: frames owed to the last event
        long drawn = 0;
        const int steps = 5 + static_cast<int>(random() % 200);
        for (int step = 0; step < steps; ++step) {
            switch (random() % 4) {
                case 0:
                    pacer.noteActivity();
                    owed = FramePacer::kSettleFrames;
                    break;
                case 1: {
                    FrameNeeds needs;
                    needs.everyFrame = random() % 5 == 0;
                    needs.withinSeconds = random() % 2 ? 0.0 : 0.01 * (1 + random() % 100);
                    const double deadline = random() % 3 ? 0.0 : 0.01 * (1 + random() % 100);
                    const FramePacer::Plan plan = pacer.plan(needs, deadline);
                    if (needs.everyFrame || owed > 0) {
                        REQUIRE(plan.wait == FramePacer::Wait::Poll);
                    } else if (needs.withinSeconds > 0.0 || deadline > 0.0) {
                        REQUIRE(plan.wait == FramePacer::Wait::Timeout);
                        double expected = 1e9;
                        if (needs.withinSeconds > 0.0) expected = needs.withinSeconds;
                        if (deadline > 0.0 && deadline < expected) expected = deadline;
                        REQUIRE(plan.seconds == expected);
                    } else {
                        REQUIRE(plan.wait == FramePacer::Wait::Forever);
                    }
                    break;
                }
                default:
                    pacer.frameDrawn();
                    ++drawn;
                    if (owed > 0) --owed;
                    break;
            }
            REQUIRE(pacer.settling() == (owed > 0));
            REQUIRE(pacer.framesDrawn() == drawn);
        }
    }
}
