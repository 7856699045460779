// Runs code that may crash or hang on hostile input (a third-party file parser) in a child process, so that a
// malformed file costs an error message, never the program or the user's work.
#pragma once

#include <functional>
#include <string>

#include "core/status.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

// What the child may do: report progress (0..1) and hand back its result bytes (once).
class IsolatedChannel {
public:
    explicit IsolatedChannel(int fd) : fd_(fd) {}
    void progress(float fraction);
    void result(const std::string& bytes);

private:
    int fd_;
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

}  // namespace sculpt::io
