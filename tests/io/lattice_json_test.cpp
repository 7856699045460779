// Lattice tool files (io/lattice_json.h): the shipped library loads, every lattice round-trips bitwise through
// its explicit form, and bad files are refused with the field named.
#include <catch2/catch.hpp>

#include <filesystem>
#include <random>

#include "core/lattice.h"
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
        REQUIRE(file.net.chunkCount() > 0);
        io::LatticeFile back;
        REQUIRE(io::parseLatticeFile(io::latticeFileText(file), "round trip", back));
        REQUIRE(back.name == file.name);
        REQUIRE(core::sameLatticeNet(back.net, file.net));
        REQUIRE(back.net.weldGroups == file.net.weldGroups);
        // The positioning command keeps it a valid lattice anywhere, at any size.
        std::mt19937 rng(60 + files);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int k = 0; k < 5; ++k) {
            core::LatticeNet placed;
            const Eigen::Vector3d normal(u(rng), u(rng), u(rng) + 1.5);
            REQUIRE(core::placeLatticeNet(file.net, Eigen::Vector3d(u(rng), u(rng), u(rng)) * 100, normal, std::pow(10.0, 3 * u(rng)), placed));
            REQUIRE(placed.weldGroups == file.net.weldGroups);
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
    };
    for (const auto& [text, field] : cases) {
        io::LatticeFile file;
        const Status s = io::parseLatticeFile(text, "bad.lattice.json", file);
        INFO(s.message);
        REQUIRE_FALSE(s);
        REQUIRE(s.message.find(field) != std::string::npos);
    }
}
