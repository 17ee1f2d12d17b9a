// The OpenCL runtime: device choice, context and queue, program builds, errors.
// Every OpenCL object is held by the RAII wrappers of CL/opencl.hpp.
#pragma once

#include "OclInclude.h"

#include <string>
#include <vector>

namespace btocl {

struct DeviceEntry {
    cl::Platform platform;
    cl::Device device;
    std::string platformName;
    std::string deviceName;
    cl_device_type type = 0;
};

// s in lower case (ASCII): device names and the environment's values match in any case.
std::string lowerCase(std::string s);

// All devices of all platforms, in platform order.
std::vector<DeviceEntry> listDevices();

// One line per device: "index: [GPU|CPU|...] platform / device".
std::string describeDevices(const std::vector<DeviceEntry>& devices);

// Chooses a device. spec: "" = env BT_OPENCL_DEVICE, else the first GPU, else the first CPU;
// "gpu" / "cpu" = the first of that type; a number = index into listDevices();
// anything else = the first device whose "platform / device" name holds spec (any case).
// Throws btOpenCLSolverError listing the devices there are when nothing matches.
DeviceEntry selectDevice(const std::string& spec);

// The device's parts of a step, timed by OpenCL profiling events (OclRuntime::beginPhase).
enum class DevicePhase { Upload, Split, Batch, Setup, Solve, Download, Count };

// Throws btOpenCLSolverError naming `what` and the error code when err != CL_SUCCESS.
void checkCl(cl_int err, const char* what);
const char* clErrorName(cl_int err);

// Pins PoCL's worker threads to cores (POCL_AFFINITY=1) unless `pin` is false or the variable is
// set: the first call in the process decides (PoCL reads it once, at the first device query).
void pinPoclWorkersOnce(bool pin);

class OclRuntime {
public:
    // pinPoclWorkers: pinPoclWorkersOnce's, before the process's first device query.
    // kernelBinaries: programs are built from the binaries made with the library where there is
    // one for this device, in kernelBinaryDirs(kernelBinaryDir) (KernelBinaries.h); else always
    // from source.
    explicit OclRuntime(const std::string& deviceSpec, bool pinPoclWorkers = true, bool kernelBinaries = true,
                        const std::string& kernelBinaryDir = "");

    const cl::Context& context() const { return m_context; }
    const cl::CommandQueue& queue() const { return m_queue; }
    const cl::Device& device() const { return m_device; }
    const std::string& deviceName() const { return m_deviceName; }
    bool isCpu() const { return m_isCpu; }
    bool hasProfiling() const { return m_profiling; }
    size_t maxWorkGroupSize() const { return m_maxWorkGroupSize; }
    size_t localMemSize() const { return m_localMemSize; }
    size_t maxAllocSize() const { return m_maxAllocSize; }
    // CL_DEVICE_MAX_COMPUTE_UNITS, at least 1.
    size_t computeUnits() const { return m_computeUnits; }
    // The device works in the host's memory (CL_DEVICE_HOST_UNIFIED_MEMORY: PoCL's CPU device),
    // unless the environment variable BT_OPENCL_TRANSFERS is "copy" (see transferByCopy).
    bool hostUnifiedMemory() const { return m_hostUnifiedMemory; }
    // From now on transfers copy even on a device that works in the host's memory: the path a
    // GPU takes, for the tests to run it on PoCL. Before the first transfer.
    void transferByCopy() { m_hostUnifiedMemory = false; }

    // Builds kernels/<file> (includes inlined). Throws with the compiler's log on failure.
    cl::Program buildProgramFile(const std::string& file, const std::string& options = "") const;
    // Builds kernels/<files> as one program: one compile where several would each pay the
    // compiler's fixed cost (PoCL: about 0.1 s a program with an empty cache).
    cl::Program buildProgramFiles(const std::vector<std::string>& files, const std::string& options = "") const;

    // Every kernel a step launches but the wide path's batch kernel (built per work-group size,
    // DeviceLayout): primitives.cl, split.cl, arrange.cl, setup.cl and solve.cl as one program,
    // built at the first call and kept. Its options: correctly rounded division and square root
    // (the split's grid must equal the host reference's bit for bit; on PoCL the other kernels'
    // code is the same with or without), and on a CPU software prefetch (btocl_shared.h).
    // With step lanes set (setStepProgramLanes), it holds the solve in lanes too (kernels/lane_solve.h).
    const cl::Program& stepProgram() const;
    // The lanes (W > 1) the step program's solve in lanes is built for; 1: none. Before the
    // program is first built.
    void setStepProgramLanes(int lanes);
    int stepProgramLanes() const { return m_stepLanes; }
    // Builds a program from source text (local includes inlined); `name` labels it in errors.
    cl::Program buildProgramSource(const std::string& source, const std::string& name,
                                   const std::string& options = "") const;

    cl::Kernel makeKernel(const cl::Program& program, const char* name) const;

    // Every program built on this runtime, with the host's time for its build, in build order.
    struct ProgramBuild {
        std::string name;
        double ms = 0;
        bool fromBinary = false;  // built from a binary made with the library, not compiled
        std::string binaryKey;    // its binary's name (kernelBinaryKey)
        cl::Program program;
    };
    const std::vector<ProgramBuild>& programBuilds() const { return m_programBuilds; }
    // Writes the binary of every program built so far into `dir`, each as <binaryKey>.bin, with the
    // code of every kernel variant the device has made for it (on PoCL): what the library's build
    // runs after a warm-up. Throws btOpenCLSolverError.
    void writeProgramBinaries(const std::string& dir) const;

    // Enqueues `kernel` over `items` work-items. With a local size the global size is rounded up
    // to a multiple of it (such kernels check their bounds); local 0 lets the device choose.
    // Nothing is enqueued for 0 items. `event`, when given, receives the launch's event.
    void launch(const cl::Kernel& kernel, size_t items, size_t local, const char* what,
                cl::Event* event = nullptr) const;

    // Phase timing: from beginPhase(ph) on, every launch and copy made through this runtime (and
    // DeviceBuffer) records its event under ph, until the next beginPhase or endPhases. phaseMs
    // sums the device time of a phase's events: call it once the queue has finished them.
    // clearPhases forgets them (at the start of a step). Without profiling, nothing is recorded.
    void beginPhase(DevicePhase phase) const { m_phase = m_profiling ? int(phase) : -1; }
    void endPhases() const { m_phase = -1; }
    void clearPhases() const;
    double phaseMs(DevicePhase phase) const;
    // The event slot for the next command of the current phase, or null when none is recorded.
    cl::Event* phaseEvent() const;

    // Bytes held by the DeviceBuffers made on this runtime (what a step keeps on the device;
    // Boost.Compute's own scratch is not counted).
    size_t bufferBytes() const { return m_bufferBytes; }
    void noteBufferBytes(size_t released, size_t allocated) const { m_bufferBytes += allocated - released; }

    // Holds every command enqueued from now on until releaseQueue(), so that a step's commands
    // are all enqueued before the device starts them: on PoCL a worker that starts the first
    // copy takes the host thread's core while the host is still enqueueing (docs/performance.md).
    // finish(), drain() and the blocking copies release
    // it first, so nothing waits on a held queue.
    void holdQueue() const;
    void releaseQueue() const noexcept;

    // Waits for the queue; turns an asynchronous device error into an exception.
    void finish(const char* what) const;
    // Waits for the queue and ignores its errors: on an error path, before the host memory that
    // queued copies read or write is freed or reused.
    void drain() const noexcept;

private:
    cl::Program programFromBinary(const std::string& key) const;

    cl::Device m_device;
    cl::Context m_context;
    cl::CommandQueue m_queue;
    std::string m_deviceName;
    bool m_isCpu = false;
    bool m_hostUnifiedMemory = false;
    bool m_profiling = false;
    bool m_kernelBinaries = true;
    std::string m_kernelBinaryDir;
    size_t m_maxWorkGroupSize = 0, m_localMemSize = 0, m_maxAllocSize = 0, m_computeUnits = 1;
    mutable size_t m_bufferBytes = 0;
    mutable int m_phase = -1;
    mutable cl::UserEvent m_gate;  // what a held queue waits on
    mutable bool m_held = false;
    mutable std::vector<cl::Event> m_phaseEvents[int(DevicePhase::Count)];
    mutable std::vector<ProgramBuild> m_programBuilds;
    mutable cl::Program m_stepProgram;
    int m_stepLanes = 1;
};

// Milliseconds between an event's start and end (0 without profiling).
double eventMs(const cl::Event& event);

// Sets a kernel's arguments in order from `first`: setArgsFrom(kernel, 2, buffer, n) is arguments 2, 3.
template <class... Args>
void setArgsFrom(cl::Kernel& kernel, cl_uint first, const Args&... args) {
    cl_uint index = first;
    (checkCl(kernel.setArg(index++, args), "setting a kernel argument"), ...);
}
// setArgs(kernel, buffer, n, params) is arguments 0, 1, 2.
template <class... Args>
void setArgs(cl::Kernel& kernel, const Args&... args) {
    setArgsFrom(kernel, 0, args...);
}

}  // namespace btocl
