#include "io/isolated_call.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <atomic>

#include "io/atomic_file.h"
#include "io/huge_pages.h"

// Defined by the sanitizer runtimes (ASan, UBSan) when the program is built with one; null otherwise.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace sculpt::io {

namespace {

std::atomic<bool> resultsThroughPipe{false};

// Records on the pipe: one byte of kind, 8 bytes of length (host order: both ends are this process's image),
// then the data. 'P': a float fraction; 'G': where the result lies in the child (a count, then address and
// size of each piece, 8 bytes each); 'R': the result's bytes.
// On the reply socket (caller to child, after a 'G'): 'D' (done: the caller has the bytes) or 'S' (send them as 'R').
void writeAll(int fd, const char* data, size_t size) {
    if (!writeAllBytes(fd, data, size)) ::_exit(3);  // the caller went away (cancelled): nothing more to do
}

void writeHeader(int fd, char kind, uint64_t size) {
    char header[9];
    header[0] = kind;
    std::memcpy(header + 1, &size, 8);
    writeAll(fd, header, sizeof header);
}

void writeRecord(int fd, char kind, const char* data, uint64_t size) {
    writeHeader(fd, kind, size);
    writeAll(fd, data, size);
}

// Copies the pieces listed in a 'G' record out of the child's memory into out (their bytes one after another).
// False when the list is malformed or the system refuses (EPERM, ENOSYS) or the child's memory is not there.
bool readChildMemory(pid_t pid, const char* list, uint64_t listSize, std::string& out) {
    uint64_t count = 0;
    if (listSize < 8) return false;
    std::memcpy(&count, list, 8);
    if (count > (listSize - 8) / 16 || listSize != 8 + 16 * count) return false;
    std::vector<iovec> remote(count);
    uint64_t total = 0;
    for (uint64_t i = 0; i < count; ++i) {
        uint64_t address = 0, size = 0;
        std::memcpy(&address, list + 8 + 16 * i, 8);
        std::memcpy(&size, list + 16 + 16 * i, 8);
        remote[i] = {reinterpret_cast<void*>(address), size};
        total += size;
    }
    out.clear();
    reserveWithHugePages(out, total);
    out.resize(total);
    // At most IOV_MAX (1024) pieces a call. A call copies less than asked only where it cannot read the child's
    // memory: a failure like any other (the result then comes through the pipe).
    size_t at = 0;
    for (size_t first = 0; first < remote.size(); first += 1024) {
        const size_t batch = std::min<size_t>(1024, remote.size() - first);
        size_t wanted = 0;
        for (size_t i = first; i < first + batch; ++i) wanted += remote[i].iov_len;
        if (wanted == 0) continue;
        iovec local{out.data() + at, wanted};
        ssize_t n;
        while ((n = ::process_vm_readv(pid, &local, 1, remote.data() + first, batch, 0)) < 0 && errno == EINTR) {
        }
        if (n != static_cast<ssize_t>(wanted)) return false;
        at += wanted;
    }
    return true;
}

}  // namespace

void setIsolatedResultsThroughPipe(bool always) { resultsThroughPipe = always; }

void IsolatedChannel::progress(float fraction) { writeRecord(fd_, 'P', reinterpret_cast<const char*>(&fraction), sizeof fraction); }

void IsolatedChannel::result(const std::vector<IsolatedPiece>& pieces) {
    uint64_t total = 0;
    for (const IsolatedPiece& p : pieces) total += p.size;
    std::vector<uint64_t> list{pieces.size()};
    for (const IsolatedPiece& p : pieces) {
        list.push_back(reinterpret_cast<uint64_t>(p.data));
        list.push_back(p.size);
    }
    writeRecord(fd_, 'G', reinterpret_cast<const char*>(list.data()), list.size() * 8);
    char reply = 0;
    ssize_t n;
    while ((n = ::read(replyFd_, &reply, 1)) < 0 && errno == EINTR) {
    }
    if (n == 1 && reply == 'S') {
        writeHeader(fd_, 'R', total);
        for (const IsolatedPiece& p : pieces) writeAll(fd_, static_cast<const char*>(p.data), p.size);
    }
}

Status runIsolated(const std::string& what, const std::function<void(IsolatedChannel&)>& work, double timeoutSeconds,
                   ObjLoadProgress* progress, std::string& bytes) {
    int fds[2], replyFds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return Status::error(what + ": cannot create a pipe (" + std::strerror(errno) + ")");
    // The replies go over a socket, not a pipe: a send to a child that died fails (MSG_NOSIGNAL) instead of
    // raising SIGPIPE in the caller.
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, replyFds) != 0) {
        const int error = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return Status::error(what + ": cannot create a pipe (" + std::strerror(error) + ")");
    }
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int error = errno;
        for (int f : {fds[0], fds[1], replyFds[0], replyFds[1]}) ::close(f);
        return Status::error(what + ": cannot start a process (" + std::strerror(error) + ")");
    }
    if (pid == 0) {
        ::close(fds[0]);
        ::close(replyFds[1]);
        // A crash must end the child: default actions for the fatal signals, whatever handlers the caller set
        // (a test framework's, a crash reporter's), which would otherwise run in the child as if in the caller.
        for (int signal : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGPIPE}) ::signal(signal, SIG_DFL);
        // Likewise a sanitizer's death callback (libFuzzer's saves the input as a crash of the caller's own).
        if (&__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
        // A reader allocates much at once (assimp's PLY element lists, the mesh, the result): on pages of its own.
        // Not under a sanitizer, whose allocator ignores malloc's settings (and would poison the heap's growth).
        if (&__sanitizer_set_death_callback == nullptr) prepareChildHeapForLargeAllocations();
        IsolatedChannel channel(fds[1], replyFds[0]);
        try {
            work(channel);
        } catch (...) {
            ::_exit(4);
        }
        ::_exit(0);
    }
    ::close(fds[1]);
    ::close(replyFds[0]);
    const int fd = fds[0], replyFd = replyFds[1];
    const auto reply = [replyFd](char answer) {
        while (::send(replyFd, &answer, 1, MSG_NOSIGNAL) < 0 && errno == EINTR) {
        }
    };
    // A large pipe buffer (1 MiB where the system allows; the default is 64 KiB) hands a big result over in few
    // wake-ups of each side.
    ::fcntl(fd, F_SETPIPE_SZ, 1 << 20);
    const auto start = std::chrono::steady_clock::now();
    std::string buffer, result;
    bool haveResult = false;
    std::string failure;
    for (;;) {
        pollfd p{fd, POLLIN, 0};
        const int ready = ::poll(&p, 1, 50);
        if (progress && progress->cancel.load()) {
            failure = "loading cancelled";
            break;
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (elapsed > timeoutSeconds) {
            failure = "did not finish in " + std::to_string(static_cast<long long>(std::ceil(timeoutSeconds))) +
                      " s (a malformed file?)";
            break;
        }
        if (ready < 0 && errno != EINTR) {
            failure = std::string("lost its process (") + std::strerror(errno) + ")";
            break;
        }
        if (ready <= 0) continue;
        // Read straight into the buffer's tail, which grows to a record's whole size once its header is in.
        const size_t before = buffer.size();
        buffer.resize(before + (1 << 20));
        const ssize_t n = ::read(fd, &buffer[before], 1 << 20);
        buffer.resize(before + static_cast<size_t>(std::max<ssize_t>(n, 0)));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;  // end of file: the child is done (or dead)
        // Consume the complete records.
        size_t at = 0;
        while (buffer.size() - at >= 9) {
            uint64_t size = 0;
            std::memcpy(&size, buffer.data() + at + 1, 8);
            if (buffer.size() - at - 9 < size) {
                if (buffer.capacity() < at + 9 + size) reserveWithHugePages(buffer, at + 9 + size + (1 << 20));
                break;
            }
            const char kind = buffer[at];
            if (kind == 'P' && size == sizeof(float) && progress) {
                float f = 0.0f;
                std::memcpy(&f, buffer.data() + at + 9, sizeof f);
                if (f > progress->fraction.load()) progress->fraction = f;
            } else if (kind == 'G') {
                if (!resultsThroughPipe.load() && readChildMemory(pid, buffer.data() + at + 9, size, result)) {
                    haveResult = true;
                    reply('D');
                } else {
                    reply('S');  // an 'R' record follows
                }
            } else if (kind == 'R') {
                if (at == 0 && size + 9 == buffer.size()) {
                    buffer.erase(0, 9);  // the usual case: the result is the whole rest; no second copy
                    result.swap(buffer);
                    haveResult = true;
                    at = 0;
                    break;
                }
                result.assign(buffer, at + 9, size);
                haveResult = true;
            }
            at += 9 + size;
        }
        buffer.erase(0, at);
    }
    ::close(fd);
    ::close(replyFd);
    int status = 0;
    if (!failure.empty()) ::kill(pid, SIGKILL);
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!failure.empty()) return Status::error(what + " " + failure);
    if (WIFSIGNALED(status))
        return Status::error(what + " crashed on this file (" + ::strsignal(WTERMSIG(status)) + "): it is malformed");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !haveResult)
        return Status::error(what + " stopped without a result (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    bytes.swap(result);
    return Status::success();
}

}  // namespace sculpt::io
