#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <system_error>

namespace sculpt::io {

namespace {

Status failure(const std::string& path, const std::string& what, int error) {
    return Status::error("cannot save '" + path + "': " + what + ": " + errnoText(error));
}

std::string parentFolder(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

std::string fileName(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// note: pid + process-wide counter + a random draw, and O_EXCL on open, so two saves (threads or
// processes) into the same folder never share a temporary file.
std::string temporaryName(const std::string& folder, const std::string& name) {
    static std::atomic<unsigned> counter{0};
    static thread_local std::mt19937_64 random{std::random_device{}()};
    char suffix[64];
    std::snprintf(suffix, sizeof suffix, ".tmp-%ld-%u-%08llx", static_cast<long>(getpid()), counter++,
                  static_cast<unsigned long long>(random() & 0xffffffffULL));
    return folder + "/." + name + suffix;
}

}  // namespace

std::string errnoText(int error) { return std::generic_category().message(error); }

bool writeAllBytes(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t written = ::write(fd, data, size);
        if (written < 0 && errno == EINTR) continue;
        if (written <= 0) return false;
        data += written;
        size -= static_cast<size_t>(written);
    }
    return true;
}

Status writeFileAtomically(const std::string& path, const std::string& contents) {
    if (path.empty()) return Status::error("cannot save: empty file name");

    // Follow a symbolic link so that replacing the file does not replace the link itself.
    std::string target = path;
    struct stat linkInfo {};
    if (::lstat(path.c_str(), &linkInfo) == 0 && S_ISLNK(linkInfo.st_mode)) {
        char* resolved = ::realpath(path.c_str(), nullptr);
        if (!resolved) return failure(path, "cannot follow the symbolic link", errno);
        target = resolved;
        std::free(resolved);
    }

    struct stat existing {};
    const bool exists = ::stat(target.c_str(), &existing) == 0;
    if (exists && S_ISDIR(existing.st_mode)) return failure(path, "the path is a folder", EISDIR);
    if (exists && !S_ISREG(existing.st_mode)) return Status::error("cannot save '" + path + "': not a regular file");
    if (!exists && errno != ENOENT) return failure(path, "cannot check the path", errno);

    const std::string folder = parentFolder(target);
    const std::string name = fileName(target);
    if (name.empty()) return failure(path, "no file name", EISDIR);

    std::string temporary;
    int fd = -1;
    for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
        temporary = temporaryName(folder, name);
        // 0666 lets the umask decide the mode of a new file, as a plain fopen would.
        fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST)
            return failure(path, "cannot create a temporary file in '" + folder + "'", errno);
    }
    if (fd < 0) return failure(path, "cannot create a unique temporary file in '" + folder + "'", EEXIST);

    // From here on every failure must remove the temporary file.
    auto abandon = [&](const std::string& what, int error) {
        if (fd >= 0) ::close(fd);
        ::unlink(temporary.c_str());
        return failure(path, what, error);
    };

    // note: keep the permission bits of the file being replaced (a 0600 file stays private).
    if (exists && ::fchmod(fd, existing.st_mode & 07777) != 0)
        return abandon("cannot copy the file's permissions", errno);
    if (!writeAllBytes(fd, contents.data(), contents.size())) return abandon("write failed", errno);
    // fsync before rename: otherwise a crash can leave the new name pointing at an empty file.
    if (::fsync(fd) != 0) return abandon("fsync failed", errno);
    const int closeResult = ::close(fd);
    fd = -1;
    if (closeResult != 0) return abandon("close failed", errno);
    if (::rename(temporary.c_str(), target.c_str()) != 0) return abandon("rename failed", errno);

    // Make the rename itself durable; failing here cannot undo the save, so it is not an error.
    const int folderFd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (folderFd >= 0) {
        ::fsync(folderFd);
        ::close(folderFd);
    }
    return Status::success();
}

}  // namespace sculpt::io
