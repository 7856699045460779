// Inputs the fuzzer found (tests/io/data/fuzz_regressions/, filled by tests/fuzz/run_fuzz.sh) and the
// fuzz seed corpus: each must load cleanly or fail with a message, and what loads must write and
// read back to the same surface (the fuzz target's own invariant).
#include <dirent.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "io/obj_mesh.h"
#include "obj_test_support.h"

namespace {

std::vector<std::string> filesIn(const std::string& folder) {
    std::vector<std::string> paths;
    if (DIR* dir = ::opendir(folder.c_str())) {
        while (const dirent* entry = ::readdir(dir)) {
            const std::string name = entry->d_name;
            if (name[0] != '.') paths.push_back(folder + "/" + name);
        }
        ::closedir(dir);
    }
    return paths;
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void requireCleanLoad(const std::string& path) {
    INFO(path);
    const std::string text = readBytes(path);
    sculpt::io::ObjMesh mesh;
    std::vector<std::string> warnings;
    const sculpt::Status status = sculpt::io::loadObjFromText(text, "input.obj", "", mesh, &warnings);
    INFO(status.message);
    if (!status) {
        REQUIRE(status.message.rfind("input.obj", 0) == 0);
        return;
    }
    REQUIRE(sculpt::io::checkObjMesh(mesh));
    std::string written;
    REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
    REQUIRE(written == text);  // saved unchanged: the file it was read from
    // Written from the arrays, as the fuzz target also does.
    mesh.source = nullptr;
    REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
    sculpt::io::ObjMesh reread;
    REQUIRE(sculpt::io::loadObjFromText(written, "written.obj", "", reread, nullptr));
    REQUIRE(reread.positions.rows() == mesh.positions.rows());
    REQUIRE(std::memcmp(reread.positions.data(), mesh.positions.data(), sizeof(double) * mesh.positions.size()) == 0);
    sculpt::test::requireSameFaceStructure(mesh, reread);  // the array writer adds normals
}

}  // namespace

TEST_CASE("obj: fuzz regressions and seed corpus load cleanly or fail with a message") {
    const std::string source = SCULPT_SOURCE_DIR;
    std::vector<std::string> paths = filesIn(source + "/tests/io/data/fuzz_regressions");
    const std::vector<std::string> corpus = filesIn(source + "/tests/fuzz/corpus");
    REQUIRE(!corpus.empty());
    paths.insert(paths.end(), corpus.begin(), corpus.end());
    for (const std::string& path : paths) requireCleanLoad(path);
}
