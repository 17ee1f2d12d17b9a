#include "FaultInjection.h"

#include <atomic>

namespace btocl {
namespace {

std::atomic<bool> g_on{false};
std::atomic<long> g_checked{0}, g_failAt{0}, g_every{0};

}  // namespace

void injectDeviceFault(long nth, bool every) {
    g_on.store(false);
    g_checked.store(0);
    g_failAt.store(nth);
    g_every.store(every ? nth : 0);
    g_on.store(nth > 0);
}

long deviceResultsChecked() { return g_checked.load(); }

cl_int injectedResult(cl_int err) {
    if (!g_on.load(std::memory_order_relaxed)) return err;
    const long k = g_checked.fetch_add(1) + 1;
    long at = g_failAt.load();
    if (k != at) return err;
    const long every = g_every.load();
    g_failAt.compare_exchange_strong(at, every ? at + every : 0);
    return CL_OUT_OF_RESOURCES;
}

}  // namespace btocl
