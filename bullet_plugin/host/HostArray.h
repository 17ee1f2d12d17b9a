// Host arrays that the device reads or writes whole each step: the step's bodies, contact points
// and results. Their storage is page-aligned, so that a device on the host's own memory (PoCL's
// CPU device) can be handed the array itself (CL_MEM_USE_HOST_PTR, DeviceBuffer::shareHost) and a
// step's upload copies nothing; or, for a device with memory of its own, it comes from a
// HostMemorySource (PinnedHostMemory.h): pinned memory, which a GPU copies from and to by DMA,
// where the driver would otherwise copy pageable memory through a pinned buffer of its own first.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace btocl {

constexpr std::size_t kHostArrayAlignment = 4096;
// Arrays of at least kHugeArrayMinBytes take whole pages of kHugePageBytes (HostArray.cpp).
constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;
constexpr std::size_t kHugeArrayMinBytes = std::size_t(4) << 20;

// Heap memory for a host array: page-aligned; a large one in whole huge pages, which the kernel is
// asked to back as such (HostArray.cpp). freeHostBytes takes the size it was allocated with.
void* allocateHostBytes(std::size_t bytes);
void freeHostBytes(void* p, std::size_t bytes) noexcept;

// Where a host array's storage may come from instead of the heap.
class HostMemorySource {
public:
    // At least `bytes`, aligned to kHostArrayAlignment; null when it has none to give (the array
    // then takes the heap).
    virtual void* allocate(std::size_t bytes) noexcept = 0;
    // Takes back what allocate gave; false for any other pointer.
    virtual bool deallocate(void* p) noexcept = 0;

protected:
    ~HostMemorySource() = default;
};

// An allocator's construct whereby an element made without a value is default-initialised (a
// trivial one left unwritten) rather than zeroed.
struct DefaultInitConstruct {
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

// Page-aligned heap memory, or the source's when one is given and has some. The source must
// outlive every array that took memory from it. A copy of an array takes the heap: the copy may
// outlive the source. A host array is written whole once sized, so its elements are not zeroed
// (DefaultInitConstruct): the gather sizes its bodies' arrays afresh each step, and zeroed them on
// the calling thread alone before its threads overwrote them.
template <class T>
struct HostArrayAllocator : DefaultInitConstruct {
    using value_type = T;
    using propagate_on_container_copy_assignment = std::true_type;
    using propagate_on_container_move_assignment = std::true_type;
    using propagate_on_container_swap = std::true_type;

    HostArrayAllocator() = default;
    explicit HostArrayAllocator(HostMemorySource* s) noexcept : source(s) {}
    template <class U>
    HostArrayAllocator(const HostArrayAllocator<U>& other) noexcept : source(other.source) {}

    T* allocate(std::size_t n) {
        if (source)
            if (void* p = source->allocate(n * sizeof(T))) return static_cast<T*>(p);
        return static_cast<T*>(allocateHostBytes(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (source && source->deallocate(p)) return;
        freeHostBytes(p, n * sizeof(T));
    }
    HostArrayAllocator select_on_container_copy_construction() const noexcept { return HostArrayAllocator(); }

    template <class U>
    bool operator==(const HostArrayAllocator<U>& other) const noexcept {
        return source == other.source;
    }
    template <class U>
    bool operator!=(const HostArrayAllocator<U>& other) const noexcept {
        return source != other.source;
    }

    HostMemorySource* source = nullptr;
};

template <class T>
using HostArray = std::vector<T, HostArrayAllocator<T>>;

// Sizes an array of a step whose elements are all written next. It regrows to twice its capacity,
// as std::vector does, but to what is asked and a quarter where that is more: a dense scene's
// contacts grow by some per cent in its first steps, and a regrowth just past the first step's
// size is fresh memory to fault in (docs/performance.md, "Arrays of a step sized with room to
// spare").
template <class T, class Allocator>
void resizeForOverwrite(std::vector<T, Allocator>& v, std::size_t n) {
    if (n > v.capacity()) v.reserve(std::max(n + n / 4, 2 * v.capacity()));
    v.resize(n);
}

// The same elements in storage from `source` (null: the heap).
template <class T>
void moveToSource(HostArray<T>& array, HostMemorySource* source) {
    if (array.get_allocator().source == source) return;
    HostArray<T> moved{HostArrayAllocator<T>(source)};
    moved.reserve(array.capacity());
    moved.assign(array.begin(), array.end());
    array = std::move(moved);
}

// std::allocator, but an element made without a value is default-initialised: a row array resized
// for rows that are all written next is not zeroed first (a joint-heavy step's joint rows were a
// memset of hundreds of KB each step).
template <class T>
struct DefaultInitAllocator : std::allocator<T>, DefaultInitConstruct {
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    using DefaultInitConstruct::construct;  // not std::allocator's, which zeroes
};

}  // namespace btocl
