// writeFileAtomically: replaces or creates, keeps permissions and links, and never half-writes.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "io/atomic_file.h"
#include "io_test_support.h"

namespace {

using sculpt::test::TempFolder;
using sculpt::test::readBytes;

std::vector<std::string> entries(const std::string& folder) {
    std::vector<std::string> names;
    if (DIR* dir = ::opendir(folder.c_str())) {
        while (const dirent* entry = ::readdir(dir)) {
            const std::string name = entry->d_name;
            if (name != "." && name != "..") names.push_back(name);
        }
        ::closedir(dir);
    }
    return names;
}

}  // namespace

TEST_CASE("atomic file: creates a new file and replaces an existing one") {
    TempFolder folder;
    const std::string path = folder.file("a.txt");
    REQUIRE(sculpt::io::writeFileAtomically(path, "first"));
    REQUIRE(readBytes(path) == "first");
    const std::string binary("x\0y\n", 4);
    REQUIRE(sculpt::io::writeFileAtomically(path, binary));
    REQUIRE(readBytes(path) == binary);
    REQUIRE(sculpt::io::writeFileAtomically(path, ""));
    REQUIRE(readBytes(path).empty());
    REQUIRE(entries(folder.path) == std::vector<std::string>{"a.txt"});
}

TEST_CASE("atomic file: keeps the permission bits of the replaced file") {
    TempFolder folder;
    const std::string path = folder.file("private.txt");
    REQUIRE(sculpt::io::writeFileAtomically(path, "v1"));
    REQUIRE(::chmod(path.c_str(), 0640) == 0);
    REQUIRE(sculpt::io::writeFileAtomically(path, "v2"));
    struct stat info {};
    REQUIRE(::stat(path.c_str(), &info) == 0);
    REQUIRE((info.st_mode & 07777) == 0640);
}

TEST_CASE("atomic file: writing through a symbolic link replaces the target and keeps the link") {
    TempFolder folder;
    REQUIRE(sculpt::io::writeFileAtomically(folder.file("real.txt"), "old"));
    REQUIRE(::symlink("real.txt", folder.file("link.txt").c_str()) == 0);
    REQUIRE(sculpt::io::writeFileAtomically(folder.file("link.txt"), "new"));
    struct stat info {};
    REQUIRE(::lstat(folder.file("link.txt").c_str(), &info) == 0);
    REQUIRE(S_ISLNK(info.st_mode));
    REQUIRE(readBytes(folder.file("real.txt")) == "new");
}

TEST_CASE("atomic file: failures name the path and the reason and leave nothing behind") {
    TempFolder folder;
    REQUIRE(sculpt::io::writeFileAtomically(folder.file("keep.txt"), "precious"));

    sculpt::Status status = sculpt::io::writeFileAtomically(folder.file("missing/x.txt"), "data");
    REQUIRE_FALSE(status);
    REQUIRE(status.message.find("missing/x.txt") != std::string::npos);
    REQUIRE(status.message.find("No such file or directory") != std::string::npos);

    REQUIRE(::mkdir(folder.file("dir").c_str(), 0755) == 0);
    status = sculpt::io::writeFileAtomically(folder.file("dir"), "data");
    REQUIRE_FALSE(status);
    REQUIRE(status.message.find("Is a directory") != std::string::npos);

    status = sculpt::io::writeFileAtomically(folder.file("keep.txt/inner"), "data");
    REQUIRE_FALSE(status);
    REQUIRE(status.message.find("Not a directory") != std::string::npos);

    status = sculpt::io::writeFileAtomically("", "data");
    REQUIRE_FALSE(status);

    // /proc accepts no new files, even from root: the create fails and the target is untouched.
    status = sculpt::io::writeFileAtomically("/proc/version", "data");
    REQUIRE_FALSE(status);
    REQUIRE(status.message.find("/proc/version") != std::string::npos);

    REQUIRE(readBytes(folder.file("keep.txt")) == "precious");
    auto names = entries(folder.path);
    std::sort(names.begin(), names.end());
    REQUIRE(names == std::vector<std::string>{"dir", "keep.txt"});
}
