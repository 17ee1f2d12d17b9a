#include "HostParallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace btocl {
namespace {

// A pause of some tens of nanoseconds in a wait on another core.
inline void pauseCore() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

// One loop: its chunks, taken from a shared counter by every thread that joins it. It lives on
// the calling thread's stack until every chunk has run and every worker that joined has left.
struct Job {
    void (*chunk)(void*, int);
    void* context;
    int numChunks;
    std::atomic<int> next{0};
    // Changed under the pool's mutex; read without it by the caller waiting awake.
    std::atomic<int> unfinished;  // chunks not yet run
    std::atomic<int> joined{0};   // workers running its chunks
    bool done() const {
        return unfinished.load(std::memory_order_acquire) == 0 && joined.load(std::memory_order_acquire) == 0;
    }
};

// How long the caller of a loop waits awake for the workers' last chunks before it sleeps: they
// mostly end within microseconds, and a sleep took tens of microseconds to wake from.
constexpr std::chrono::microseconds kDoneAwake{100};

// Workers that sleep on a condition variable between loops. The caller publishes its job,
// wakes them, runs chunks itself, and waits until the job is done and left.
class HostPool {
public:
    HostPool() {
        const unsigned hw = std::thread::hardware_concurrency();
        m_threads = int(std::max(1u, std::min(hw, 64u)));
        for (int t = 1; t < m_threads; ++t) m_workers.emplace_back([this] { work(); });
    }
    ~HostPool() {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_stopping = true;
        }
        m_wake.notify_all();
        for (std::thread& w : m_workers) w.join();
    }
    int threads() const { return m_threads; }

    void run(int numChunks, void (*chunk)(void*, int), void* context) {
        // One loop at a time; a chunk that starts a loop of its own, or a second thread, runs it here.
        std::unique_lock<std::mutex> busy(m_busy, std::try_to_lock);
        if (!busy.owns_lock() || t_insideChunk || m_workers.empty()) {
            for (int c = 0; c < numChunks; ++c) chunk(context, c);
            return;
        }
        Job job{chunk, context, numChunks, {0}, numChunks};
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_job = &job;
            ++m_generation;
            m_published.store(m_generation, std::memory_order_release);
        }
        m_wake.notify_all();
        const int ran = runChunks(job);
        std::unique_lock<std::mutex> lock(m_mutex);
        job.unfinished -= ran;
        if (!job.done()) {
            lock.unlock();
            const auto until = std::chrono::steady_clock::now() + kDoneAwake;
            for (int spins = 1; !job.done(); ++spins) {
                if (spins % 64 == 0 && std::chrono::steady_clock::now() > until) break;  // a worker descheduled
                pauseCore();
            }
            lock.lock();
            m_done.wait(lock, [&] { return job.done(); });
        }
        m_job = nullptr;  // a worker that wakes only now finds nothing to join
    }

    void prewake(std::chrono::microseconds spin) {
        if (m_workers.empty()) return;
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            ++m_prewakes;
            m_spinUntil.store((std::chrono::steady_clock::now() + spin).time_since_epoch().count(),
                              std::memory_order_relaxed);
        }
        m_wake.notify_all();
    }

    // Ends a pre-wake's deadline: the workers sleep once their loops are done.
    void rest() { m_spinUntil.store(0, std::memory_order_relaxed); }

    bool awake() const {
        return !m_workers.empty() && std::chrono::steady_clock::now().time_since_epoch().count() <
                                         m_spinUntil.load(std::memory_order_relaxed);
    }

private:
    void work() {
        unsigned long seen = 0, seenPrewakes = 0;
        for (;;) {
            Job* job = nullptr;
            {
                std::unique_lock<std::mutex> lock(m_mutex);
                m_wake.wait(lock, [&] { return m_stopping || m_generation != seen || m_prewakes != seenPrewakes; });
                if (m_stopping) return;
                if (m_generation == seen) {
                    // Woken ahead of a loop: wait for it awake, up to the deadline, then sleep again.
                    seenPrewakes = m_prewakes;
                    lock.unlock();
                    waitAwake(seen);
                    continue;
                }
                seenPrewakes = m_prewakes;
                seen = m_generation;
                job = m_job;
                if (!job) continue;
                ++job->joined;
            }
            const int ran = runChunks(*job);
            {
                std::lock_guard<std::mutex> lock(m_mutex);
                job->unfinished -= ran;
                --job->joined;
                if (job->done()) m_done.notify_all();
            }
            // Within a pre-wake's deadline the next loop of the same step is near: wait for it
            // awake, as for the first, rather than sleep and be woken again for each loop.
            waitAwake(seen);
        }
    }

    // Yields until a loop newer than `seen` is published or the pre-wake's deadline passes.
    void waitAwake(unsigned long seen) {
        while (m_published.load(std::memory_order_acquire) == seen && awake()) std::this_thread::yield();
    }

    static int runChunks(Job& job) {
        t_insideChunk = true;
        int ran = 0;
        for (int c = job.next.fetch_add(1); c < job.numChunks; c = job.next.fetch_add(1)) {
            job.chunk(job.context, c);
            ++ran;
        }
        drainStreamedStores();  // a chunk's stores past the caches, before its count
        t_insideChunk = false;
        return ran;
    }

    static thread_local bool t_insideChunk;
    int m_threads = 1;
    std::vector<std::thread> m_workers;
    std::mutex m_busy;   // held by the thread whose loop the pool runs
    std::mutex m_mutex;  // guards m_job, m_generation, m_stopping and the jobs' counts
    std::condition_variable m_wake, m_done;
    Job* m_job = nullptr;
    unsigned long m_generation = 0;
    std::atomic<unsigned long> m_published{0};  // m_generation, for workers that wait awake
    unsigned long m_prewakes = 0;
    // The pre-wake's deadline (steady_clock ticks): read by every loop, so not under the mutex.
    std::atomic<std::chrono::steady_clock::rep> m_spinUntil{0};
    bool m_stopping = false;
};

thread_local bool HostPool::t_insideChunk = false;

HostPool& pool() {
    static HostPool p;
    return p;
}

// runSharedSteps' steps: which parts are taken, how many have run.
struct SharedSteps {
    int numSteps, shares;
    void (*part)(void*, int, int);
    void* context;
    std::unique_ptr<std::atomic<int>[]> taken;   // per step and share
    std::unique_ptr<std::atomic<int>[]> joined;  // per share: a thread runs it
    std::atomic<int> done{0};                    // parts run
};

// Spins (each a pause, some tens of nanoseconds) a thread waits on the others before it takes a
// part they have not taken: a part with nothing in it would otherwise take the next at once. A
// share no thread has joined yet (the pool's worker still waking, or the pool taken by another
// loop) is taken at once.
constexpr int kTakeAfterSpins = 32;
// Spins after which a waiting thread yields its core: the thread it waits on may want it.
constexpr int kYieldAfterSpins = 4096;

bool take(SharedSteps& s, int step, int share) {
    std::atomic<int>& flag = s.taken[size_t(step) * size_t(s.shares) + size_t(share)];
    return flag.load(std::memory_order_relaxed) == 0 && flag.exchange(1, std::memory_order_acq_rel) == 0;
}

void runPart(SharedSteps& s, int step, int share) {
    s.part(s.context, step, share);
    s.done.fetch_add(1, std::memory_order_release);
}

void runShare(void* context, int share) {
    SharedSteps& s = *static_cast<SharedSteps*>(context);
    s.joined[size_t(share)].store(1, std::memory_order_relaxed);
    for (int step = 0; step < s.numSteps; ++step) {
        if (take(s, step, share)) runPart(s, step, share);
        const int doneAfter = (step + 1) * s.shares;
        for (int spins = 0; s.done.load(std::memory_order_acquire) < doneAfter; ++spins) {
            for (int other = 0; other < s.shares; ++other)
                if ((spins >= kTakeAfterSpins || !s.joined[size_t(other)].load(std::memory_order_relaxed)) &&
                    take(s, step, other))
                    runPart(s, step, other);
            if (spins < kYieldAfterSpins)
                pauseCore();
            else
                std::this_thread::yield();
        }
    }
}

}  // namespace

void runSharedSteps(int numSteps, int shares, bool onPool, void (*part)(void*, int, int), void* context) {
    if (numSteps <= 0) return;
    shares = std::max(1, shares);
    if (shares == 1) {
        for (int step = 0; step < numSteps; ++step) part(context, step, 0);
        return;
    }
    SharedSteps s{numSteps, shares, part, context, std::make_unique<std::atomic<int>[]>(size_t(numSteps) * size_t(shares)),
                  std::make_unique<std::atomic<int>[]>(size_t(shares))};
    if (onPool)
        runChunks(shares, runShare, &s);
    else
        runShare(&s, 0);  // every part on this thread
}

int hostThreads() { return pool().threads(); }

void drainStreamedStores() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_sfence();
#endif
}

void prewakeHostThreads(std::chrono::microseconds spin) { pool().prewake(spin); }

void restHostThreads() { pool().rest(); }

bool hostThreadsAwake() { return pool().awake(); }

void runChunks(int numChunks, void (*chunk)(void* context, int c), void* context) {
    pool().run(numChunks, chunk, context);
}

}  // namespace btocl
