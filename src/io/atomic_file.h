// Crash-safe file replacement: a save either fully happens or leaves the old file as it was.
#pragma once

#include <cstddef>
#include <string>

#include "core/status.h"

namespace sculpt::io {

// Writes contents to path atomically: a uniquely named temporary file in the same folder (so the
// rename cannot cross file systems) is written, fsync'ed and renamed over path. A symbolic link at
// path is followed, so the link survives and its target is replaced. An existing file's permission
// bits are kept; a new file gets 0666 minus the umask.
// On any failure the temporary file is removed, path is untouched, and the error names the path and
// the system's reason (errno text). POSIX only.
Status writeFileAtomically(const std::string& path, const std::string& contents);

// The system's text for errno value `error` ("No such file or directory").
std::string errnoText(int error);

// Writes all `size` bytes of `data` to file descriptor `fd`, retrying short writes and EINTR. False when a
// write fails or writes nothing (errno tells why); what was written before stays written.
bool writeAllBytes(int fd, const char* data, std::size_t size);

}  // namespace sculpt::io
