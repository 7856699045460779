#include "io/isolated_call.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>

// Defined by the sanitizer runtimes (ASan, UBSan) when the program is built with one; null otherwise.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace sculpt::io {

namespace {

// Records on the pipe: one byte of kind, 8 bytes of length (host order: both ends are this process's image),
// then the data. 'P': a float fraction; 'R': the result.
void writeAll(int fd, const char* data, size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) ::_exit(3);  // the caller went away (cancelled): nothing more to do
        data += n;
        size -= static_cast<size_t>(n);
    }
}

void writeRecord(int fd, char kind, const char* data, uint64_t size) {
    char header[9];
    header[0] = kind;
    std::memcpy(header + 1, &size, 8);
    writeAll(fd, header, sizeof header);
    writeAll(fd, data, size);
}

}  // namespace

void IsolatedChannel::progress(float fraction) { writeRecord(fd_, 'P', reinterpret_cast<const char*>(&fraction), sizeof fraction); }

void IsolatedChannel::result(const std::string& bytes) { writeRecord(fd_, 'R', bytes.data(), bytes.size()); }

Status runIsolated(const std::string& what, const std::function<void(IsolatedChannel&)>& work, double timeoutSeconds,
                   ObjLoadProgress* progress, std::string& bytes) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return Status::error(what + ": cannot create a pipe (" + std::strerror(errno) + ")");
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int error = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return Status::error(what + ": cannot start a process (" + std::strerror(error) + ")");
    }
    if (pid == 0) {
        ::close(fds[0]);
        // A crash must end the child: default actions for the fatal signals, whatever handlers the caller set
        // (a test framework's, a crash reporter's), which would otherwise run in the child as if in the caller.
        for (int signal : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGPIPE}) ::signal(signal, SIG_DFL);
        // Likewise a sanitizer's death callback (libFuzzer's saves the input as a crash of the caller's own).
        if (&__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
        IsolatedChannel channel(fds[1]);
        try {
            work(channel);
        } catch (...) {
            ::_exit(4);
        }
        ::_exit(0);
    }
    ::close(fds[1]);
    const int fd = fds[0];
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
                if (buffer.capacity() < at + 9 + size) buffer.reserve(at + 9 + size + (1 << 20));
                break;
            }
            const char kind = buffer[at];
            if (kind == 'P' && size == sizeof(float) && progress) {
                float f = 0.0f;
                std::memcpy(&f, buffer.data() + at + 9, sizeof f);
                if (f > progress->fraction.load()) progress->fraction = f;
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
