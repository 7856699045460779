// Lattice tool files (io/lattice_json.h): the shipped library loads, every lattice round-trips bitwise through
// its explicit form, and bad files are refused with the field named.
#include <catch2/catch.hpp>

#include <filesystem>
#include <random>

#include "core/volume/lattice.h"
#include "core/volume/volume_kinds.h"
#include "io/lattice_json.h"

using namespace sculpt;

TEST_CASE("lattice files: the shipped library loads and round-trips bitwise", "[io][net]") {
    const std::filesystem::path folder = std::filesystem::path(SCULPT_SOURCE_DIR) / "assets" / "lattices";
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        if (entry.path().extension() != ".json") continue;
        ++files;
        io::LatticeFile file;
        const Status read = io::readLatticeFile(entry.path().string(), file);
        INFO(entry.path() << ": " << read.message);
        REQUIRE(read);
        REQUIRE(file.volume->chunkCount() > 0);
        io::LatticeFile back;
        REQUIRE(io::parseLatticeFile(io::latticeFileText(file), "round trip", back));
        REQUIRE(back.name == file.name);
        REQUIRE(core::sameVolume(*back.volume, *file.volume));
        REQUIRE(back.volume->weldGroupList() == file.volume->weldGroupList());
        // The positioning command keeps it a valid lattice anywhere, at any size.
        std::mt19937 rng(60 + files);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int k = 0; k < 5; ++k) {
            std::shared_ptr<const core::Volume> placed;
            const Eigen::Vector3d normal(u(rng), u(rng), u(rng) + 1.5);
            REQUIRE(core::placeVolume(*file.volume, Eigen::Vector3d(u(rng), u(rng), u(rng)) * 100, normal, std::pow(10.0, 3 * u(rng)), placed));
            REQUIRE(placed->weldGroupList() == file.volume->weldGroupList());
        }
    }
    REQUIRE(files >= 4);
}

TEST_CASE("lattice files: bad files are refused with the field named", "[io][net]") {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "cylinder", "base": [0,0,0], "axis": [0,0,1], "radius": -1, "height": 1, "chunks": [1,4,1]}})", "radius"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "sphere", "centre": [0,0,0], "radius": 1, "chunks": [1,2,2]}})", "angular"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "blob"}})", "kind"},
        {R"({"format": "dmffd-lattice", "version": 2, "lattice": {}})", "version"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "net", "count": [2,2,2], "degree": [1,1,1], "points": [[0,0,0]]}})", "points"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "parallelepiped", "origin": [0,0,0], "edges": [[1,0,0],[0,1,0],[0,0,-1]], "chunks": [1,1,1]}})", "right-handed"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "net", "count": [3,2,2], "degree": [1,1,1], "knots": [[0,0,0.7,0.2,1],[],[]], "points": [[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,0],[2,1,0],[0,0,1],[1,0,1],[2,0,1],[0,1,1],[1,1,1],[2,1,1]]}})", "lattice.knots[0]: knot 3 is smaller"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "net", "count": [3,2,2], "degree": [1,1,1], "knots": [[0,0,0.5,1],[],[]], "points": [[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,0],[2,1,0],[0,0,1],[1,0,1],[2,0,1],[0,1,1],[1,1,1],[2,1,1]]}})", "lattice.knots[0]: 4 knots"},
        {R"({"format": "dmffd-lattice", "version": 1, "lattice": {"kind": "net", "count": [3,2,2], "degree": [1,1,1], "knots": [[0,0,0.5,1,1]], "points": []}})", "lattice.knots: expected 3"},
    };
    for (const auto& [text, field] : cases) {
        io::LatticeFile file;
        const Status s = io::parseLatticeFile(text, "bad.lattice.json", file);
        INFO(s.message);
        REQUIRE_FALSE(s);
        REQUIRE(s.message.find(field) != std::string::npos);
    }
}

TEST_CASE("lattice files: the S loft loads as a valid loft and freezes its points back to their parameters", "[io][net][netedit]") {
    io::LatticeFile file;
    const std::string path = std::string(SCULPT_SOURCE_DIR) + "/assets/lattices/s_loft.lattice.json";
    const Status read = io::readLatticeFile(path, file);
    INFO(read.message);
    REQUIRE(read);
    const core::LatticeNet& net = *file.volume->tensorNet();
    REQUIRE(net.kind == "loft");
    REQUIRE(net.count == std::array<int, 3>{4, 2, 17});
    REQUIRE(net.degree == std::array<int, 3>{2, 1, 2});
    REQUIRE(net.weldGroups.empty());
    REQUIRE(net.boundaryFace[2][0]);
    REQUIRE(net.boundaryFace[2][1]);
    // Points of the volume at random parameters are frozen back to those parameters (3.3).
    std::mt19937 rng(62);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int sample = 0; sample < 200; ++sample) {
        const Eigen::Vector3d t(u(rng), u(rng), u(rng));
        Eigen::Vector3d x, back;
        core::evaluateNetVolume(net, net.rest, t, x);
        INFO("t = " << t.transpose());
        REQUIRE(core::freezePoint(net, net.rest, net.restIndex, x, back));
        REQUIRE((back - t).cwiseAbs().maxCoeff() <= 1e-9);
    }
    // The sections follow the S: the first is at the top right, the middle one at the centre, the last at the
    // bottom left.
    REQUIRE(net.rest.row(0).y() > 0.5);
    REQUIRE(net.rest.row(net.slotCount() - 1).y() < -0.5);
}

TEST_CASE("lattice files: loft sections by placement or by points, and bad lofts named", "[io][net][netedit]") {
    const std::string profile = R"("profile": {"min": [-1, -0.5], "max": [1, 0.5], "chunks": [1, 1], "degree": [1, 1]})";
    const std::string placed = R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [
        {"origin": [0, 0, 0]}, {"origin": [0.2, 0, 1], "u_axis": [2, 0, 0], "v_axis": [0.5, 1, 0], "scale": [1.5, 2]}]})";
    const std::string points = R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [
        [[-1, -0.5, 0], [1, -0.5, 0], [-1, 0.5, 0], [1, 0.5, 0]], [[-1.3, -1, 1], [1.7, -1, 1], [-1.3, 1, 1], [1.7, 1, 1]]]})";
    core::LatticeNet a, b;
    REQUIRE(io::parseLatticeNetJson(nlohmann::json::parse(placed), "lattice", a));
    REQUIRE(io::parseLatticeNetJson(nlohmann::json::parse(points), "lattice", b));
    REQUIRE(a.kind == "loft");
    REQUIRE((a.rest - b.rest).cwiseAbs().maxCoeff() <= 1e-15);
    // The explicit form round-trips.
    core::LatticeNet back;
    REQUIRE(io::parseLatticeNetJson(io::latticeNetJson(a), "lattice", back));
    REQUIRE(core::sameLatticeNet(a, back));

    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"kind": "loft", )" + profile + R"(, "sections": [{"origin": [0, 0, 0]}, {"origin": [0, 0, 1]}]})", "needs 3 to 64 sections"},
        {R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [{"origin": [0, 0, 0]}, [[0, 0, 1]]]})", "lattice.sections[1]: expected 4 [x,y,z] points"},
        {R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [{"origin": [0, 0, 0], "u_axis": [0, 0, 0]}, {"origin": [0, 0, 1]}]})", "lattice.sections[0]: u_axis and v_axis"},
        {R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [{"origin": [0, 0, 0], "scale": -1}, {"origin": [0, 0, 1]}]})", "lattice.sections[0].scale"},
        {R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [{"origin": [0, 0, 0], "twist": 1}, {"origin": [0, 0, 1]}]})", "lattice.sections[0].twist: unknown field"},
        {R"({"kind": "loft", )" + profile + R"(, "degree": 1, "sections": [{"origin": [0, 0, 1]}, {"origin": [0, 0, 0]}]})", "left-handed"},
        {R"({"kind": "loft", )" + profile + R"(, "degree": 1})", "lattice.sections: missing"},
    };
    for (const auto& [text, message] : cases) {
        core::LatticeNet net;
        const Status s = io::parseLatticeNetJson(nlohmann::json::parse(text), "lattice", net);
        INFO(text << " / " << s.message);
        REQUIRE_FALSE(s);
        REQUIRE(s.message.find(message) != std::string::npos);
    }
}
