#include "KernelWarmUp.h"

#include <chrono>

namespace btocl {

void KernelWarmUp::launch(const cl::Kernel& kernel, size_t items, size_t local) {
    const auto t0 = std::chrono::steady_clock::now();
    m_rt.launch(kernel, items, local, "launching a kernel to warm it up");
    if (!m_timeEach) return;
    finish();
    Timing t;
    checkCl(kernel.getInfo(CL_KERNEL_FUNCTION_NAME, &t.kernel), "reading a kernel's name");
    t.local = local;
    t.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    m_timings.push_back(t);
}

cl::Buffer KernelWarmUp::zeros(size_t bytes) const {
    cl_int err = CL_SUCCESS;
    cl::Buffer b(m_rt.context(), CL_MEM_READ_WRITE, bytes, nullptr, &err);
    checkCl(err, "allocating a warm-up buffer");
    const cl_uchar zero = 0;
    checkCl(m_rt.queue().enqueueFillBuffer(b, zero, 0, bytes), "clearing a warm-up buffer");
    return b;
}

}  // namespace btocl
