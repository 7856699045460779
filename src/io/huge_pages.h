// Transparent huge pages for large, freshly allocated buffers.
//
// On a virtual machine a page fault costs microseconds, and a buffer of 100 MB touched for the first time takes
// 25,000 of them at 4 KiB: most of the time of loading a 1M-vertex mesh through the reader process went there
// (io_bench load_ply_1m). Where the system's THP setting is "madvise" (Debian's default), a buffer advised
// before it is first written is backed by 2 MiB pages instead: 512 times fewer faults.
#pragma once

#include <cstddef>

namespace sculpt::io {

// Advises the whole 2 MiB-aligned pages inside [data, data + bytes) to be backed by huge pages. Does nothing
// for buffers under 4 MiB or where the system refuses (no THP, THP "never"): advice only, never an error.
// Call it before the buffer's pages are first written; pages already in memory are not changed.
void adviseHugePages(const void* data, size_t bytes);

// c.reserve(n) for a std::vector or std::string, its storage advised as above. When the reservation allocates
// anew (c was shorter), a following assign, resize or append fills it without 4 KiB faults; what c held is
// copied over first (its pages stay small).
template <typename Container>
void reserveWithHugePages(Container& c, size_t n) {
    c.reserve(n);
    adviseHugePages(c.data(), c.capacity() * sizeof(typename Container::value_type));
}

// For a short-lived child process (runIsolated's reader) that inherited its parent's heap: gives back the heap's
// free pages, which the child would otherwise copy page by page on first write (copy-on-write after fork), and
// has every later allocation come from the heap, advised for huge pages. Changes malloc's settings for the rest
// of this process: call it only in such a child, first thing.
void prepareChildHeapForLargeAllocations();

}  // namespace sculpt::io
