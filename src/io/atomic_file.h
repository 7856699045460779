// Crash-safe file replacement: a save either fully happens or leaves the old file as it was.
#pragma once

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

}  // namespace sculpt::io
