#include "PinnedHostMemory.h"

#include <cstdint>

namespace btocl {

PinnedHostMemory::PinnedHostMemory(const OclRuntime& rt) : m_rt(rt) {
    cl_int err = CL_SUCCESS;
    m_queue = cl::CommandQueue(rt.context(), rt.device(), 0, &err);
    checkCl(err, "creating the command queue of the pinned host memory");
}

PinnedHostMemory::~PinnedHostMemory() {
    const std::lock_guard<std::mutex> lock(m_mutex);
    for (auto& entry : m_blocks) release(entry.second);
    m_blocks.clear();
}

void* PinnedHostMemory::allocate(std::size_t bytes) noexcept {
    // A page more than asked for: the arrays promise page alignment, and drivers map at their own
    // (PoCL at 128 bytes).
    const std::size_t mappedBytes = bytes + kHostArrayAlignment;
    if (bytes == 0 || mappedBytes > m_rt.maxAllocSize()) return nullptr;
    cl_int err = CL_SUCCESS;
    cl::Buffer buffer(m_rt.context(), CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, mappedBytes, nullptr, &err);
    if (err != CL_SUCCESS) return nullptr;
    void* mapped =
        m_queue.enqueueMapBuffer(buffer, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, mappedBytes, nullptr, nullptr, &err);
    if (err != CL_SUCCESS || !mapped) return nullptr;
    const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(mapped);
    void* p = reinterpret_cast<void*>((at + kHostArrayAlignment - 1) / kHostArrayAlignment * kHostArrayAlignment);
    Block block{buffer, mapped, bytes};
    try {
        const std::lock_guard<std::mutex> lock(m_mutex);
        m_blocks.emplace(p, block);
        m_bytes += bytes;
        return p;
    } catch (...) {  // no room to note it: the heap instead
    }
    release(block);
    return nullptr;
}

bool PinnedHostMemory::deallocate(void* p) noexcept {
    const std::lock_guard<std::mutex> lock(m_mutex);
    const auto found = m_blocks.find(p);
    if (found == m_blocks.end()) return false;
    release(found->second);
    m_bytes -= found->second.bytes;
    m_blocks.erase(found);
    return true;
}

std::size_t PinnedHostMemory::bytesHeld() const {
    const std::lock_guard<std::mutex> lock(m_mutex);
    return m_bytes;
}

void PinnedHostMemory::release(const Block& block) noexcept {
    // Unmapped before the buffer goes: a buffer released while mapped stays with the driver.
    m_queue.enqueueUnmapMemObject(block.buffer, block.mapped);
    m_queue.finish();
}

}  // namespace btocl
