// The window's choice between deforming on the CPU and in the vertex shader (app/deformation_path.h): it
// measures drag frames on both paths on a big mesh, skipping each path's first (switching) frame, and keeps the
// one whose median frame is shorter; still frames are timed once per path and decide the path at rest; small
// meshes stay on the CPU.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "app/deformation_path.h"

using sculpt::app::DeformationPath;
using sculpt::app::DeformationPathChooser;

namespace {

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

}  // namespace

TEST_CASE("deformation path: small meshes stay on the CPU without measuring", "[app][deformation_path]") {
    DeformationPathChooser chooser;
    for (int vertices : {0, 1, 5000, DeformationPathChooser::kDefaultMinVertices - 1}) {
        chooser.reset(vertices);
        CHECK(chooser.dragPath() == DeformationPath::Cpu);
        CHECK(chooser.restPath() == DeformationPath::Cpu);
        CHECK_FALSE(chooser.deciding());
        CHECK_FALSE(chooser.wantsStillFrame(DeformationPath::Cpu));
        chooser.addDragFrame(DeformationPath::Cpu, 100.0);
        CHECK(chooser.dragPath() == DeformationPath::Cpu);
        CHECK(chooser.label(true) == "CPU");
        CHECK(chooser.describe().find("small") != std::string::npos);
    }
    CHECK(chooser.decidedFor(10));
    CHECK_FALSE(chooser.decidedFor(DeformationPathChooser::kDefaultMinVertices));
}

TEST_CASE("deformation path: a big mesh measures both paths and keeps the one with the shorter median frame",
          "[app][deformation_path]") {
    std::mt19937 rng(1201);
    for (int trial = 0; trial < 200; ++trial) {
        DeformationPathChooser chooser;
        chooser.reset(DeformationPathChooser::kDefaultMinVertices + int(rng() % 5000000));
        REQUIRE(chooser.deciding());
        REQUIRE(chooser.dragPath() == DeformationPath::Gpu);  // measured first: where a real GPU stays
        REQUIRE(chooser.restPath() == DeformationPath::Cpu);  // but at rest the CPU until both are known
        CHECK(chooser.label(false) == "CPU");
        std::lognormal_distribution<double> gpuFrame(std::log(1.0 + rng() % 40), 0.5), cpuFrame(std::log(1.0 + rng() % 40), 0.5);
        std::vector<double> counted[2];  // [0] CPU, [1] GPU: the frames that count, kept independently
        int frames = 0;
        bool first = true;
        DeformationPath previous = DeformationPath::Gpu;
        while (chooser.deciding() && frames < 100) {
            const DeformationPath path = chooser.dragPath();
            CHECK(chooser.restPath() == DeformationPath::Cpu);
            const double ms = path == DeformationPath::Gpu ? gpuFrame(rng) : cpuFrame(rng);
            // Noise the chooser must ignore: a frame reported for the other path, and nonsense times.
            chooser.addDragFrame(path == DeformationPath::Gpu ? DeformationPath::Cpu : DeformationPath::Gpu, 0.001);
            chooser.addDragFrame(path, std::numeric_limits<double>::quiet_NaN());
            chooser.addDragFrame(path, -1.0);
            chooser.addDragFrame(path, ms);
            ++frames;
            // The first frame on each path pays the switch and does not count.
            if (!first && path == previous) counted[path == DeformationPath::Gpu ? 1 : 0].push_back(ms);
            first = false;
            previous = path;
        }
        INFO("trial " << trial);
        REQUIRE_FALSE(chooser.deciding());
        CHECK(frames == 2 * (DeformationPathChooser::kFramesPerPath + 1));
        REQUIRE(counted[0].size() == size_t(DeformationPathChooser::kFramesPerPath));
        REQUIRE(counted[1].size() == size_t(DeformationPathChooser::kFramesPerPath));
        CHECK(chooser.medianMs(DeformationPath::Cpu) == median(counted[0]));
        CHECK(chooser.label(false) != "CPU (timing)");
        CHECK(chooser.medianMs(DeformationPath::Gpu) == median(counted[1]));
        const DeformationPath expected = median(counted[1]) < median(counted[0]) ? DeformationPath::Gpu : DeformationPath::Cpu;
        CHECK(chooser.dragPath() == expected);
        CHECK(chooser.describe().find(std::string("While dragging: the ") + (expected == DeformationPath::Gpu ? "GPU" : "CPU")) == 0);
        // Decided: frames change nothing; a new mesh measures again.
        chooser.addDragFrame(chooser.dragPath(), 1e9);
        CHECK(chooser.dragPath() == expected);

        // At rest: the CPU when it won the drags; after a GPU win, the GPU until its still frame is timed, then
        // the GPU only if that frame took at most 1.25 times the CPU's.
        std::uniform_real_distribution<double> stillOf(1.0, 500.0);
        const double cpuStill = stillOf(rng), gpuStill = stillOf(rng);
        REQUIRE(chooser.wantsStillFrame(DeformationPath::Cpu));
        chooser.addStillFrame(DeformationPath::Cpu, cpuStill);
        CHECK_FALSE(chooser.wantsStillFrame(DeformationPath::Cpu));
        chooser.addStillFrame(DeformationPath::Cpu, 1e9);  // only the first counts
        CHECK(chooser.stillMs(DeformationPath::Cpu) == cpuStill);
        if (expected == DeformationPath::Cpu) {
            CHECK(chooser.restPath() == DeformationPath::Cpu);
            CHECK(chooser.label(false) == "CPU");
        } else {
            CHECK(chooser.restPath() == DeformationPath::Gpu);
            chooser.addStillFrame(DeformationPath::Gpu, gpuStill);
            const DeformationPath rest = gpuStill <= 1.25 * cpuStill ? DeformationPath::Gpu : DeformationPath::Cpu;
            CHECK(chooser.restPath() == rest);
            CHECK(chooser.label(false) == (rest == DeformationPath::Gpu ? "GPU" : "GPU drag, CPU rest"));
        }
        chooser.reset(DeformationPathChooser::kDefaultMinVertices);
        CHECK(chooser.deciding());
        CHECK(chooser.stillMs(DeformationPath::Cpu) < 0.0);
    }
}

TEST_CASE("deformation path: a forced path is every frame's, until the next mesh", "[app][deformation_path]") {
    DeformationPathChooser chooser;
    chooser.reset(DeformationPathChooser::kDefaultMinVertices);
    for (const DeformationPath path : {DeformationPath::Gpu, DeformationPath::Cpu}) {
        chooser.force(path);
        CHECK(chooser.dragPath() == path);
        CHECK(chooser.restPath() == path);
        CHECK_FALSE(chooser.deciding());
        CHECK_FALSE(chooser.wantsStillFrame(path));
        CHECK(chooser.label(false) == std::string(path == DeformationPath::Gpu ? "GPU" : "CPU") + " (chosen)");
    }
    chooser.reset(DeformationPathChooser::kDefaultMinVertices);
    CHECK(chooser.deciding());
    CHECK(chooser.restPath() == DeformationPath::Cpu);
}
