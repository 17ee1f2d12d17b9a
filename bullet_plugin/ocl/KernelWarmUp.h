// Kernels compiled before a step needs them. PoCL (the CPU device) generates a kernel's code at
// its first launch, once per local size, and again for a grid of 65,535 work-items or more (its
// "smallgrid" specialisation): with an empty cache that is tens to hundreds of milliseconds a
// kernel, paid by whichever step first launches it. Each device stage launches its kernels here
// once, on no work (counts of 0, scratch buffers), with the local size its steps use and a grid of
// kGrid work-items where the step's grid follows its counts: the large variant made first then
// serves every smaller grid of the process too (PoCL reuses a loaded kernel for any grid up to the
// one it was made for), so a step never meets a kernel or variant that is not ready.
#pragma once

#include "OclRuntime.h"

#include <string>
#include <vector>

namespace btocl {

class KernelWarmUp {
public:
    // Work-items of a warm-up launch whose step launch grows with the step: past PoCL's smallgrid
    // limit (65,535), a multiple of every work-group size up to 1,024.
    static constexpr size_t kGrid = 65536;

    // With `timeEach`, every launch is waited for on its own and timed (startup's per-kernel
    // figures); else the launches are waited for together, by finish().
    explicit KernelWarmUp(const OclRuntime& rt, bool timeEach = false) : m_rt(rt), m_timeEach(timeEach) {}

    // Enqueues `kernel`, its arguments set so that no work-item does any work, over `items`
    // work-items in work-groups of `local` (0: the device chooses, as the step's launch lets it).
    void launch(const cl::Kernel& kernel, size_t items, size_t local);

    // A new buffer of `bytes` zero bytes, for arguments that no work-item of a warm-up reads past.
    // Not counted among the solver's buffers (OclRuntime::bufferBytes): it lives for the warm-up.
    cl::Buffer zeros(size_t bytes) const;

    // Waits for every launch: each kernel is compiled and has run. Throws btOpenCLSolverError.
    void finish() const { m_rt.finish("warming the kernels up"); }

    struct Timing {
        std::string kernel;
        size_t local = 0;
        double ms = 0;  // host time from the enqueue to the finish: the compile, mostly
    };
    const std::vector<Timing>& timings() const { return m_timings; }

private:
    const OclRuntime& m_rt;
    bool m_timeEach;
    std::vector<Timing> m_timings;
};

}  // namespace btocl
