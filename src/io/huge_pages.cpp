#include "io/huge_pages.h"

#include <malloc.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sculpt::io {

namespace {

constexpr uintptr_t kHugePage = uintptr_t(2) << 20;

void adviseRange(uintptr_t begin, uintptr_t end) {
    const uintptr_t from = (begin + kHugePage - 1) & ~(kHugePage - 1), to = end & ~(kHugePage - 1);
    if (to > from) ::madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);  // advice: failure is fine
}

}  // namespace

void adviseHugePages(const void* data, size_t bytes) {
    if (data == nullptr || bytes < 2 * kHugePage) return;
    const uintptr_t begin = reinterpret_cast<uintptr_t>(data);
    adviseRange(begin, begin + bytes);
}

void prepareChildHeapForLargeAllocations() {
    // Free chunks' whole pages go back (MADV_DONTNEED): the child gets fresh pages there, not copies.
    ::malloc_trim(0);
    // Every allocation from the heap (no separate mappings, which would not be advised), grown 1 GiB at a time
    // (address space only: pages come when written) and never shrunk (the child is short-lived).
    ::mallopt(M_MMAP_MAX, 0);
    ::mallopt(M_TRIM_THRESHOLD, 1 << 30);
    ::mallopt(M_TOP_PAD, 1 << 30);
    // Grow the heap now: a block larger than all its free memory cannot fit in any free chunk.
    const struct mallinfo2 info = ::mallinfo2();
    std::free(std::malloc(info.fordblks + (size_t(64) << 20)));
    // Then advise the whole heap, its new top included.
    uintptr_t begin = 0, end = 0;
    if (std::FILE* maps = std::fopen("/proc/self/maps", "r")) {
        char line[512];
        while (std::fgets(line, sizeof line, maps))
            if (std::strstr(line, "[heap]") != nullptr) {
                unsigned long b = 0, e = 0;
                if (std::sscanf(line, "%lx-%lx", &b, &e) == 2) begin = b, end = e;
            }
        std::fclose(maps);
    }
    if (end > begin) adviseRange(begin, end);
}

}  // namespace sculpt::io
