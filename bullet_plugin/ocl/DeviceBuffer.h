// A typed device buffer that grows and is reused from step to step.
#pragma once

#include "HostArray.h"
#include "OclRuntime.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace btocl {

template <class T>
class DeviceBuffer {
public:
    DeviceBuffer() = default;
    DeviceBuffer(const DeviceBuffer&) = delete;  // one owner: its bytes are counted on the runtime
    DeviceBuffer& operator=(const DeviceBuffer&) = delete;
    ~DeviceBuffer() {
        if (m_rt) m_rt->noteBufferBytes(m_capacity * sizeof(T), 0);
    }

    // Room for at least n elements. Grows by half again on overflow; contents are lost on growth.
    // A new buffer has a quarter to spare: a scene's contacts grow for a few steps while it
    // settles, and every regrowth is fresh memory to fault in (about 3 s a GiB on the
    // test machines' VMs: at 1M contact points it made the second step 4x slower than the third).
    void reserve(const OclRuntime& rt, size_t n) {
        if (n <= m_capacity && m_buffer() && !m_sharedHost) return;
        size_t cap = std::max<size_t>({n + n / 4, m_capacity + m_capacity / 2, 64});
        if (cap * sizeof(T) > rt.maxAllocSize()) cap = std::max(n, rt.maxAllocSize() / sizeof(T));
        if (n * sizeof(T) > rt.maxAllocSize())
            throw btOpenCLSolverError("btOpenCLConstraintSolver: a buffer of " + std::to_string(n * sizeof(T)) +
                                      " bytes exceeds the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE of " +
                                      std::to_string(rt.maxAllocSize()));
        cl_int err = CL_SUCCESS;
        cl::Buffer grown(rt.context(), CL_MEM_READ_WRITE, cap * sizeof(T), nullptr, &err);
        checkCl(err, "allocating a device buffer");
        rt.noteBufferBytes(m_capacity * sizeof(T), cap * sizeof(T));
        m_buffer = grown;
        m_capacity = cap;
        m_sharedHost = nullptr;
        m_rt = &rt;
    }

    // Hands the host array's elements to the device for the step's commands, which must end
    // before the host writes the array again. On a device that works in the host's memory
    // (PoCL's CPU device: OclRuntime::hostUnifiedMemory) the buffer is the array itself
    // (shareHost), and a map and unmap hand the host's writes over without a copy. Elsewhere the
    // elements are copied, as enqueueWrite.
    void enqueueUpload(const OclRuntime& rt, const HostArray<T>& host) {
        if (!rt.hostUnifiedMemory()) {
            enqueueWrite(rt, host.data(), host.size());
            return;
        }
        if (host.empty()) return;
        shareHost(rt, host);
        enqueueMapAndUnmap(rt, CL_MAP_WRITE_INVALIDATE_REGION, host.size());
    }

    // The buffer a kernel writes the step's results to, for enqueueDownload(host) to hand back:
    // the host array itself on a device that works in the host's memory, else room for its
    // elements. The array keeps its size until the download.
    void prepareDownload(const OclRuntime& rt, HostArray<T>& host) {
        if (rt.hostUnifiedMemory() && !host.empty())
            shareHost(rt, host);
        else
            reserve(rt, host.size());
    }

    // Enqueues the hand-back of what the kernels wrote to the host array (prepareDownload):
    // a map and unmap where it is the buffer (PoCL: no copy), else a copy. Valid once the queue
    // is finished.
    void enqueueDownload(const OclRuntime& rt, HostArray<T>& host) {
        if (host.empty()) return;
        if (m_sharedHost == host.data() && m_capacity == host.capacity()) {
            enqueueMapAndUnmap(rt, CL_MAP_READ, host.size());
            return;
        }
        enqueueRead(rt, host.data(), host.size());
    }

    // Copies from host memory and waits for the copy.
    void write(const OclRuntime& rt, const T* data, size_t n) {
        reserve(rt, n);
        if (n == 0) return;
        rt.releaseQueue();  // a blocking copy must not wait on a held queue
        checkCl(rt.queue().enqueueWriteBuffer(m_buffer, CL_TRUE, 0, n * sizeof(T), data, nullptr, rt.phaseEvent()),
                "writing a device buffer");
    }
    void write(const OclRuntime& rt, const std::vector<T>& data) { write(rt, data.data(), data.size()); }

    // Enqueues the copy without waiting: `data` must stay unchanged until the queue is finished.
    void enqueueWrite(const OclRuntime& rt, const T* data, size_t n) {
        reserve(rt, n);
        if (n == 0) return;
        checkCl(rt.queue().enqueueWriteBuffer(m_buffer, CL_FALSE, 0, n * sizeof(T), data, nullptr, rt.phaseEvent()),
                "writing a device buffer");
    }
    template <class Allocator>
    void enqueueWrite(const OclRuntime& rt, const std::vector<T, Allocator>& data) {
        enqueueWrite(rt, data.data(), data.size());
    }

    // Enqueues the copy back of elements [offset, offset + n) without waiting: `data` is valid
    // once the queue is finished.
    void enqueueRead(const OclRuntime& rt, T* data, size_t n, size_t offset = 0) const {
        if (n == 0) return;
        checkCl(rt.queue().enqueueReadBuffer(m_buffer, CL_FALSE, offset * sizeof(T), n * sizeof(T), data, nullptr,
                                             rt.phaseEvent()),
                "reading a device buffer");
    }

    // Copies elements [offset, offset + n) back and waits for them.
    void read(const OclRuntime& rt, T* data, size_t n, size_t offset = 0) const {
        if (n == 0) return;
        rt.releaseQueue();  // a blocking copy must not wait on a held queue
        checkCl(rt.queue().enqueueReadBuffer(m_buffer, CL_TRUE, offset * sizeof(T), n * sizeof(T), data, nullptr,
                                             rt.phaseEvent()),
                "reading a device buffer");
    }
    std::vector<T> read(const OclRuntime& rt, size_t n) const {
        std::vector<T> out(n);
        read(rt, out.data(), n);
        return out;
    }

    void fill(const OclRuntime& rt, const T& value, size_t n) {
        reserve(rt, n);
        if (n == 0) return;
        checkCl(rt.queue().enqueueFillBuffer(m_buffer, value, 0, n * sizeof(T), nullptr, rt.phaseEvent()),
                "filling a device buffer");
    }

    const cl::Buffer& buffer() const { return m_buffer; }
    size_t capacity() const { return m_capacity; }

private:
    // This buffer made over the host array's storage (CL_MEM_USE_HOST_PTR over its page-aligned
    // memory), again only when the array moved.
    void shareHost(const OclRuntime& rt, const HostArray<T>& host) {
        if (m_sharedHost == host.data() && m_capacity == host.capacity()) return;
        cl_int err = CL_SUCCESS;
        cl::Buffer shared(rt.context(), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, host.capacity() * sizeof(T),
                          const_cast<T*>(host.data()), &err);
        checkCl(err, "making a device buffer over host memory");
        rt.noteBufferBytes(m_capacity * sizeof(T), host.capacity() * sizeof(T));
        m_buffer = shared;
        m_capacity = host.capacity();
        m_sharedHost = host.data();
        m_rt = &rt;
    }

    // Synchronises the first n elements between the device and the host array it is made over.
    void enqueueMapAndUnmap(const OclRuntime& rt, cl_map_flags flags, size_t n) {
        cl_int mapErr = CL_SUCCESS;
        void* mapped = rt.queue().enqueueMapBuffer(m_buffer, CL_FALSE, flags, 0, n * sizeof(T), nullptr, nullptr, &mapErr);
        // A mapping is unmapped whatever is checked after it: a buffer released while mapped
        // stays with the driver.
        const cl_int unmapErr = mapped ? rt.queue().enqueueUnmapMemObject(m_buffer, mapped, nullptr, rt.phaseEvent())
                                       : CL_SUCCESS;
        checkCl(mapErr, "mapping a device buffer over host memory");
        checkCl(unmapErr, "unmapping a device buffer over host memory");
    }

    cl::Buffer m_buffer;
    size_t m_capacity = 0;
    const T* m_sharedHost = nullptr;  // the host array the buffer is made over (shareHost), or null
    const OclRuntime* m_rt = nullptr;  // the runtime its bytes are counted on
};

}  // namespace btocl
