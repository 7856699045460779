// The window's choice between deforming on the CPU and in the vertex shader (app/deformation_path.h): it
// measures both paths on a big mesh, skipping each path's first (switching) frame, and keeps the one whose
// median frame is shorter; small meshes stay on the CPU.
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
        CHECK(chooser.path() == DeformationPath::Cpu);
        CHECK_FALSE(chooser.deciding());
        chooser.addFrame(DeformationPath::Cpu, 100.0);
        CHECK(chooser.path() == DeformationPath::Cpu);
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
        REQUIRE(chooser.path() == DeformationPath::Gpu);  // measured first: where a real GPU stays
        std::lognormal_distribution<double> gpuFrame(std::log(1.0 + rng() % 40), 0.5), cpuFrame(std::log(1.0 + rng() % 40), 0.5);
        std::vector<double> counted[2];  // [0] CPU, [1] GPU: the frames that count, kept independently
        int frames = 0;
        bool first = true;
        DeformationPath previous = DeformationPath::Gpu;
        while (chooser.deciding() && frames < 100) {
            const DeformationPath path = chooser.path();
            const double ms = path == DeformationPath::Gpu ? gpuFrame(rng) : cpuFrame(rng);
            // Noise the chooser must ignore: a frame reported for the other path, and nonsense times.
            chooser.addFrame(path == DeformationPath::Gpu ? DeformationPath::Cpu : DeformationPath::Gpu, 0.001);
            chooser.addFrame(path, std::numeric_limits<double>::quiet_NaN());
            chooser.addFrame(path, -1.0);
            chooser.addFrame(path, ms);
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
        CHECK(chooser.medianMs(DeformationPath::Gpu) == median(counted[1]));
        const DeformationPath expected = median(counted[1]) < median(counted[0]) ? DeformationPath::Gpu : DeformationPath::Cpu;
        CHECK(chooser.path() == expected);
        CHECK(chooser.describe().find(expected == DeformationPath::Gpu ? "GPU" : "CPU") == 0);
        // Decided: frames change nothing; a new mesh measures again.
        chooser.addFrame(chooser.path(), 1e9);
        CHECK(chooser.path() == expected);
        chooser.reset(DeformationPathChooser::kDefaultMinVertices);
        CHECK(chooser.deciding());
    }
}
