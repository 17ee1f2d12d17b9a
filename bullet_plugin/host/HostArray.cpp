#include "HostArray.h"

#include <sys/mman.h>

namespace btocl {
namespace {

// A large array (a block's lane rows, points, impulses, bodies) is read at random or streamed
// many times a step: on 4 KiB pages its lookups overflow the TLB, and its growth costs a page
// fault a page. Arrays from kHugeArrayMinBytes take whole huge pages of their own, advised as
// such (transparent huge pages, where the kernel offers them on request; a hint, nothing else
// changes).

bool takesHugePages(std::size_t bytes) { return bytes >= kHugeArrayMinBytes; }

std::size_t wholeHugePages(std::size_t bytes) { return (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1); }

}  // namespace

void* allocateHostBytes(std::size_t bytes) {
    if (!takesHugePages(bytes)) return ::operator new(bytes, std::align_val_t(kHostArrayAlignment));
    const std::size_t whole = wholeHugePages(bytes);
    void* p = ::operator new(whole, std::align_val_t(kHugePageBytes));
#ifdef MADV_HUGEPAGE
    madvise(p, whole, MADV_HUGEPAGE);
#endif
    return p;
}

void freeHostBytes(void* p, std::size_t bytes) noexcept {
    if (!takesHugePages(bytes)) return ::operator delete(p, std::align_val_t(kHostArrayAlignment));
    ::operator delete(p, std::align_val_t(kHugePageBytes));
}

}  // namespace btocl
