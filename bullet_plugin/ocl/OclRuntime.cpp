#include "OclRuntime.h"

#include "FaultInjection.h"
#include "KernelBinaries.h"
#include "KernelSources.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <sstream>

namespace btocl {
std::string lowerCase(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    const auto e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

const char* typeName(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return "GPU";
    if (t & CL_DEVICE_TYPE_CPU) return "CPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "ACCELERATOR";
    return "OTHER";
}

}  // namespace

const char* clErrorName(cl_int err) {
    switch (err) {
#define BTOCL_ERR(e) case e: return #e;
        BTOCL_ERR(CL_SUCCESS) BTOCL_ERR(CL_DEVICE_NOT_FOUND) BTOCL_ERR(CL_DEVICE_NOT_AVAILABLE)
        BTOCL_ERR(CL_COMPILER_NOT_AVAILABLE) BTOCL_ERR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        BTOCL_ERR(CL_OUT_OF_RESOURCES) BTOCL_ERR(CL_OUT_OF_HOST_MEMORY) BTOCL_ERR(CL_BUILD_PROGRAM_FAILURE)
        BTOCL_ERR(CL_INVALID_VALUE) BTOCL_ERR(CL_INVALID_DEVICE) BTOCL_ERR(CL_INVALID_CONTEXT)
        BTOCL_ERR(CL_INVALID_COMMAND_QUEUE) BTOCL_ERR(CL_INVALID_MEM_OBJECT) BTOCL_ERR(CL_INVALID_PROGRAM)
        BTOCL_ERR(CL_INVALID_PROGRAM_EXECUTABLE) BTOCL_ERR(CL_INVALID_KERNEL_NAME) BTOCL_ERR(CL_INVALID_KERNEL)
        BTOCL_ERR(CL_INVALID_ARG_INDEX) BTOCL_ERR(CL_INVALID_ARG_VALUE) BTOCL_ERR(CL_INVALID_ARG_SIZE)
        BTOCL_ERR(CL_INVALID_KERNEL_ARGS) BTOCL_ERR(CL_INVALID_WORK_DIMENSION)
        BTOCL_ERR(CL_INVALID_WORK_GROUP_SIZE) BTOCL_ERR(CL_INVALID_WORK_ITEM_SIZE)
        BTOCL_ERR(CL_INVALID_GLOBAL_OFFSET) BTOCL_ERR(CL_INVALID_EVENT_WAIT_LIST) BTOCL_ERR(CL_INVALID_EVENT)
        BTOCL_ERR(CL_INVALID_OPERATION) BTOCL_ERR(CL_INVALID_BUFFER_SIZE) BTOCL_ERR(CL_INVALID_GLOBAL_WORK_SIZE)
        BTOCL_ERR(CL_INVALID_BUILD_OPTIONS) BTOCL_ERR(CL_PLATFORM_NOT_FOUND_KHR)
        BTOCL_ERR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
#undef BTOCL_ERR
        default: return "unknown OpenCL error";
    }
}

void checkCl(cl_int err, const char* what) {
    err = injectedResult(err);
    if (err == CL_SUCCESS) return;
    std::ostringstream ss;
    ss << "btOpenCLConstraintSolver: " << what << " failed: " << clErrorName(err) << " (" << err << ")";
    throw btOpenCLSolverError(ss.str());
}

// PoCL's CPU device runs a work-group per worker thread, and the serial path's claimed solve
// (kernels/solve.cl, solveStepClaimed) keeps one running on every compute unit for the whole
// step, waiting on each other between sets. Unpinned, Linux at times woke both workers of a
// 2-core machine on one core, which ran the step at one core's speed; pinned (POCL_AFFINITY=1),
// every step ran at two (docs/performance.md). PoCL reads the variable when it starts its
// workers, at the process's first device query: the first call decides, and a value the user
// set is kept. Once per process: setenv may not run beside another thread's getenv, and solvers
// made in threads at once would race here.
void pinPoclWorkersOnce(bool pin) {
    static std::once_flag once;
    std::call_once(once, [pin] {
        if (pin && std::getenv("POCL_AFFINITY") == nullptr) setenv("POCL_AFFINITY", "1", 0);
    });
}

std::vector<DeviceEntry> listDevices() {
    pinPoclWorkersOnce(true);
    std::vector<DeviceEntry> out;
    std::vector<cl::Platform> platforms;
    if (cl::Platform::get(&platforms) != CL_SUCCESS) return out;
    for (const cl::Platform& p : platforms) {
        std::vector<cl::Device> devices;
        if (p.getDevices(CL_DEVICE_TYPE_ALL, &devices) != CL_SUCCESS) continue;
        for (const cl::Device& d : devices) {
            DeviceEntry e;
            e.platform = p;
            e.device = d;
            e.platformName = trim(p.getInfo<CL_PLATFORM_NAME>());
            e.deviceName = trim(d.getInfo<CL_DEVICE_NAME>());
            e.type = d.getInfo<CL_DEVICE_TYPE>();
            out.push_back(e);
        }
    }
    return out;
}

std::string describeDevices(const std::vector<DeviceEntry>& devices) {
    if (devices.empty()) return "  (no OpenCL platform or device found; is an ICD such as pocl-opencl-icd installed?)\n";
    std::ostringstream ss;
    for (size_t i = 0; i < devices.size(); ++i)
        ss << "  " << i << ": [" << typeName(devices[i].type) << "] " << devices[i].platformName << " / "
           << devices[i].deviceName << "\n";
    return ss.str();
}

DeviceEntry selectDevice(const std::string& specIn) {
    std::string spec = trim(specIn);
    bool fromEnvironment = false;
    if (spec.empty())
        if (const char* env = std::getenv("BT_OPENCL_DEVICE")) {
            spec = trim(env);
            fromEnvironment = true;
        }
    const std::vector<DeviceEntry> devices = listDevices();
    if (devices.empty())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: no OpenCL device found.\n" + describeDevices(devices));

    auto firstOfType = [&](cl_device_type t) -> const DeviceEntry* {
        for (const DeviceEntry& d : devices)
            if (d.type & t) return &d;
        return nullptr;
    };
    const std::string key = lowerCase(spec);
    const DeviceEntry* found = nullptr;
    if (key.empty()) {
        found = firstOfType(CL_DEVICE_TYPE_GPU);
        if (!found) found = firstOfType(CL_DEVICE_TYPE_CPU);
        if (!found) found = &devices.front();
    } else if (key == "gpu") {
        found = firstOfType(CL_DEVICE_TYPE_GPU);
    } else if (key == "cpu") {
        found = firstOfType(CL_DEVICE_TYPE_CPU);
    } else if (std::all_of(key.begin(), key.end(), [](unsigned char c) { return std::isdigit(c); })) {
        const size_t index = std::strtoul(key.c_str(), nullptr, 10);
        if (index < devices.size()) found = &devices[index];
    } else {
        for (const DeviceEntry& d : devices)
            if (lowerCase(d.platformName + " / " + d.deviceName).find(key) != std::string::npos) {
                found = &d;
                break;
            }
    }
    if (!found)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: no OpenCL device matches '" + spec + "' (" +
                                  (fromEnvironment ? "the environment variable BT_OPENCL_DEVICE, read because "
                                                     "btOpenCLSolverConfig::device is empty"
                                                   : "btOpenCLSolverConfig::device") +
                                  "). Devices there are:\n" + describeDevices(devices) +
                                  "Choose one by index, by 'gpu' or 'cpu', or by part of its name.");
    return *found;
}

OclRuntime::OclRuntime(const std::string& deviceSpec, bool pinPoclWorkers, bool kernelBinaries,
                       const std::string& kernelBinaryDir)
    : m_kernelBinaries(kernelBinaries), m_kernelBinaryDir(kernelBinaryDir) {
    pinPoclWorkersOnce(pinPoclWorkers);
    const DeviceEntry entry = selectDevice(deviceSpec);
    m_device = entry.device;
    m_deviceName = entry.platformName + " / " + entry.deviceName;
    m_isCpu = (entry.type & CL_DEVICE_TYPE_CPU) != 0;

    cl_int err = CL_SUCCESS;
    m_context = cl::Context(m_device, nullptr, nullptr, nullptr, &err);
    checkCl(err, "creating the OpenCL context");
    m_queue = cl::CommandQueue(m_context, m_device, CL_QUEUE_PROFILING_ENABLE, &err);
    m_profiling = (err == CL_SUCCESS);
    if (!m_profiling) {
        m_queue = cl::CommandQueue(m_context, m_device, 0, &err);
        checkCl(err, "creating the OpenCL command queue");
    }
    m_maxWorkGroupSize = m_device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
    m_computeUnits = std::max<cl_uint>(1, m_device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
    m_hostUnifiedMemory = m_device.getInfo<CL_DEVICE_HOST_UNIFIED_MEMORY>() == CL_TRUE;
    if (const char* env = std::getenv("BT_OPENCL_TRANSFERS"); env && *env) {
        const std::string value = env, key = lowerCase(value);
        if (key == "copy")
            transferByCopy();
        else if (key != "auto")
            throw btOpenCLSolverError("btOpenCLConstraintSolver: BT_OPENCL_TRANSFERS is '" + value +
                                      "'; it takes auto or copy");
    }
    m_localMemSize = m_device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
    m_maxAllocSize = m_device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
}

cl::Program OclRuntime::buildProgramFile(const std::string& file, const std::string& options) const {
    return buildProgramSource(loadKernelSource(file), file, options);
}

cl::Program OclRuntime::buildProgramFiles(const std::vector<std::string>& files, const std::string& options) const {
    std::string name;
    for (const std::string& f : files) name += (name.empty() ? "" : " + ") + f;
    return buildProgramSource(loadKernelSources(files), name, options);
}

const cl::Program& OclRuntime::stepProgram() const {
    if (!m_stepProgram())
        m_stepProgram = buildProgramFiles({"primitives.cl", "split.cl", "arrange.cl", "setup.cl", "solve.cl"},
                                          std::string("-cl-fp32-correctly-rounded-divide-sqrt") +
                                              (m_isCpu ? " -DBTOCL_CPU_PREFETCH -DBTOCL_NO_CONTRACTION" : "") +
                                              (m_stepLanes > 1 ? " -DBTOCL_LANES=" + std::to_string(m_stepLanes) : ""));
    return m_stepProgram;
}

void OclRuntime::setStepProgramLanes(int lanes) {
    if (lanes == m_stepLanes) return;
    if (m_stepProgram())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: the step program's lanes were set after it was built");
    m_stepLanes = lanes;
}

cl::Program OclRuntime::buildProgramSource(const std::string& source, const std::string& name,
                                           const std::string& options) const {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string text = inlineKernelIncludes(source);
    const std::string opts = "-cl-std=CL1.2 " + options;
    ProgramBuild build{name, 0, false, kernelBinaryKey(text, opts, m_device), cl::Program()};
    if (m_kernelBinaries) build.program = programFromBinary(build.binaryKey);
    build.fromBinary = build.program() != nullptr;
    if (!build.fromBinary) {
        cl_int err = CL_SUCCESS;
        build.program = cl::Program(m_context, text, false, &err);
        checkCl(err, ("creating program " + name).c_str());
        err = build.program.build(std::vector<cl::Device>{m_device}, opts.c_str());
        if (err != CL_SUCCESS) {
            std::string log;
            build.program.getBuildInfo(m_device, CL_PROGRAM_BUILD_LOG, &log);
            throw btOpenCLSolverError("btOpenCLConstraintSolver: building kernel program '" + name + "' failed (" +
                                      clErrorName(err) + ") on " + m_deviceName + ". Compiler log:\n" + log);
        }
    }
    build.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    m_programBuilds.push_back(build);
    return build.program;
}

// A program from the binary named `key`, built; a null program when there is none or the device
// refuses it (another device or driver, a damaged file): then the caller compiles the source.
cl::Program OclRuntime::programFromBinary(const std::string& key) const {
    const std::vector<unsigned char> bytes = readKernelBinary(kernelBinaryDirs(m_kernelBinaryDir), key);
    if (bytes.empty()) return cl::Program();
    const unsigned char* data = bytes.data();
    const size_t size = bytes.size();
    cl_int status = CL_SUCCESS, err = CL_SUCCESS;
    cl_program raw = clCreateProgramWithBinary(m_context(), 1, &m_device(), &size, &data, &status, &err);
    if (err != CL_SUCCESS || status != CL_SUCCESS || !raw) return cl::Program();
    cl::Program program(raw);  // takes the reference
    if (program.build(std::vector<cl::Device>{m_device}) != CL_SUCCESS) return cl::Program();
    return program;
}

void OclRuntime::writeProgramBinaries(const std::string& dir) const {
    for (const ProgramBuild& build : m_programBuilds) {
        size_t size = 0;
        checkCl(clGetProgramInfo(build.program(), CL_PROGRAM_BINARY_SIZES, sizeof size, &size, nullptr),
                "reading a program's binary size");
        std::vector<unsigned char> bytes(size);
        unsigned char* data = bytes.data();
        checkCl(clGetProgramInfo(build.program(), CL_PROGRAM_BINARIES, sizeof data, &data, nullptr),
                "reading a program's binary");
        writeKernelBinary(dir, build.binaryKey, bytes);
    }
}

cl::Kernel OclRuntime::makeKernel(const cl::Program& program, const char* name) const {
    cl_int err = CL_SUCCESS;
    cl::Kernel k(program, name, &err);
    checkCl(err, (std::string("creating kernel ") + name).c_str());
    return k;
}

void OclRuntime::clearPhases() const {
    for (std::vector<cl::Event>& events : m_phaseEvents) events.clear();
}

cl::Event* OclRuntime::phaseEvent() const {
    if (m_phase < 0) return nullptr;
    m_phaseEvents[m_phase].emplace_back();
    return &m_phaseEvents[m_phase].back();
}

double OclRuntime::phaseMs(DevicePhase phase) const {
    double ms = 0;
    for (const cl::Event& e : m_phaseEvents[int(phase)]) ms += eventMs(e);
    return ms;
}

void OclRuntime::launch(const cl::Kernel& kernel, size_t items, size_t local, const char* what,
                        cl::Event* event) const {
    if (items == 0) return;
    if (!event) event = phaseEvent();
    const size_t global = local ? (items + local - 1) / local * local : items;
    checkCl(m_queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global),
                                         local ? cl::NDRange(local) : cl::NullRange, nullptr, event),
            what);
}

void OclRuntime::holdQueue() const {
    releaseQueue();
    cl_int err = CL_SUCCESS;
    m_gate = cl::UserEvent(m_context, &err);
    checkCl(err, "creating a user event");
    const std::vector<cl::Event> gate{m_gate};
    m_held = true;
    try {
        checkCl(m_queue.enqueueMarkerWithWaitList(&gate), "holding the queue");
    } catch (...) {
        releaseQueue();
        throw;
    }
}

void OclRuntime::releaseQueue() const noexcept {
    if (!m_held) return;
    m_held = false;
    m_gate.setStatus(CL_COMPLETE);
    m_queue.flush();
}

void OclRuntime::finish(const char* what) const {
    releaseQueue();
    checkCl(m_queue.finish(), what);
}

void OclRuntime::drain() const noexcept {
    releaseQueue();
    m_queue.finish();
}

double eventMs(const cl::Event& event) {
    if (!event()) return 0;
    cl_ulong start = 0, end = 0;
    if (event.getProfilingInfo(CL_PROFILING_COMMAND_START, &start) != CL_SUCCESS) return 0;
    if (event.getProfilingInfo(CL_PROFILING_COMMAND_END, &end) != CL_SUCCESS) return 0;
    return end > start ? double(end - start) * 1e-6 : 0.0;
}

}  // namespace btocl
