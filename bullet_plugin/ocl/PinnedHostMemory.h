// Pinned host memory for the step's host arrays (HostArray.h) on a device with memory of its own
// (a GPU): buffers made with CL_MEM_ALLOC_HOST_PTR and kept mapped, so the host writes the step's
// records straight into memory the device copies from by DMA, and reads the results where the
// device copied them. From pageable memory a driver first copies through a pinned buffer of its
// own (NVIDIA's OpenCL guide: pinned transfers run at several times the rate).
#pragma once

#include "HostArray.h"
#include "OclRuntime.h"

#include <cstddef>
#include <mutex>
#include <unordered_map>

namespace btocl {

class PinnedHostMemory final : public HostMemorySource {
public:
    // Maps and unmaps on a queue of its own, so that an allocation never waits on the step's
    // commands (a held queue, OclRuntime::holdQueue). `rt` must outlive this object, and this
    // object every array that took memory from it.
    explicit PinnedHostMemory(const OclRuntime& rt);
    ~PinnedHostMemory();
    PinnedHostMemory(const PinnedHostMemory&) = delete;
    PinnedHostMemory& operator=(const PinnedHostMemory&) = delete;

    // Null when the device cannot make or map such a buffer (past CL_DEVICE_MAX_MEM_ALLOC_SIZE,
    // say): the array then takes the heap, and its copies run as from any host memory.
    void* allocate(std::size_t bytes) noexcept override;
    bool deallocate(void* p) noexcept override;

    // Pinned bytes held now.
    std::size_t bytesHeld() const;

private:
    struct Block {
        cl::Buffer buffer;
        void* mapped = nullptr;  // where the map put it; the array starts at the next page
        std::size_t bytes = 0;
    };
    void release(const Block& block) noexcept;

    const OclRuntime& m_rt;
    cl::CommandQueue m_queue;
    mutable std::mutex m_mutex;
    std::unordered_map<void*, Block> m_blocks;  // by the pointer allocate gave
    std::size_t m_bytes = 0;
};

}  // namespace btocl
