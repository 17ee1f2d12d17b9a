// Host arrays that a device on the host's own memory (PoCL's CPU device) can read in place:
// page-aligned, so that a buffer made over them with CL_MEM_USE_HOST_PTR is that memory itself
// and a step's upload copies nothing (DeviceBuffer::shareHost).
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace btocl {

constexpr std::size_t kHostArrayAlignment = 4096;

template <class T>
struct PageAlignedAllocator {
    using value_type = T;
    PageAlignedAllocator() = default;
    template <class U>
    PageAlignedAllocator(const PageAlignedAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(kHostArrayAlignment)));
    }
    void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t(kHostArrayAlignment)); }
    template <class U>
    bool operator==(const PageAlignedAllocator<U>&) const noexcept { return true; }
    template <class U>
    bool operator!=(const PageAlignedAllocator<U>&) const noexcept { return false; }
};

template <class T>
using HostArray = std::vector<T, PageAlignedAllocator<T>>;

}  // namespace btocl
