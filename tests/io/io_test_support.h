// Shared helpers for the io tests: a temporary folder under the build tree and whole-file reads.
#pragma once

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>
#include <stdlib.h>

namespace sculpt::test {

// A fresh folder under the build tree, removed with its files at scope exit.
struct TempFolder {
    std::string path;
    explicit TempFolder(const std::string& prefix = "io_test") {
        std::string pattern = std::string(SCULPT_BINARY_DIR) + "/" + prefix + "_XXXXXX";
        REQUIRE(::mkdtemp(pattern.data()) != nullptr);
        path = pattern;
    }
    ~TempFolder() { std::system(("rm -rf '" + path + "'").c_str()); }
    std::string file(const std::string& name) const { return path + "/" + name; }
};

inline std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace sculpt::test
