// Runs code that may crash or hang on hostile input (a third-party file parser) in a child process, so that a
// malformed file costs an error message, never the program or the user's work.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/status.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

// A piece of the child's result: bytes in the child's memory, which must stay there until result() returns.
struct IsolatedPiece {
    const void* data = nullptr;
    size_t size = 0;
};

// What the child may do: report progress (0..1) and hand back its result (once).
class IsolatedChannel {
public:
    IsolatedChannel(int fd, int replyFd) : fd_(fd), replyFd_(replyFd) {}
    void progress(float fraction);
    void result(const std::string& bytes) { result({IsolatedPiece{bytes.data(), bytes.size()}}); }
    // The result is the pieces' bytes one after another. The caller copies them straight out of this process's
    // memory (process_vm_readv: one copy, none through the pipe), or, where the system does not allow that
    // (a container's seccomp profile, Yama's ptrace scope 3), this sends them through the pipe.
    void result(const std::vector<IsolatedPiece>& pieces);

private:
    int fd_, replyFd_;
};

// Forks; the child runs work(channel) and exits without running destructors or atexit handlers (_exit), so it
// shares nothing with the caller but the pipe. The caller waits, forwarding the child's progress to `progress`
// (may be null; its fraction is raised, never lowered) and polling its cancel flag every 50 ms.
// On success `bytes` holds what the child passed to channel.result. Fails, naming `what` ("the PLY reader"):
//   - the child died from a signal ("crashed (Segmentation fault)") or exited without a result;
//   - it ran longer than timeoutSeconds (it is killed: "did not finish in 12 s");
//   - the caller cancelled (it is killed; the message ends in "cancelled");
//   - fork or pipe failed (the system's reason).
// The child must not use threads the caller started (OpenMP pools, ...): it has only the calling thread.
Status runIsolated(const std::string& what, const std::function<void(IsolatedChannel&)>& work, double timeoutSeconds,
                   ObjLoadProgress* progress, std::string& bytes);

// For tests: when true, every result comes through the pipe (the path taken where reading the child's memory
// is not allowed). Off by default.
void setIsolatedResultsThroughPipe(bool always);

}  // namespace sculpt::io
