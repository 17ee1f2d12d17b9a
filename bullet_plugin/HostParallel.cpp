#include "HostParallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace btocl {
namespace {

// Workers that sleep on a condition variable between loops. A loop is published as a new
// generation; each thread takes chunks from a shared counter, and the caller, once out of
// chunks, waits for the last one to finish.
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
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_chunk = chunk;
            m_context = context;
            m_numChunks = numChunks;
            m_nextChunk.store(0);
            m_unfinished = numChunks;
            ++m_generation;
        }
        m_wake.notify_all();
        runChunksHere();
        std::unique_lock<std::mutex> lock(m_mutex);
        m_done.wait(lock, [this] { return m_unfinished == 0; });
    }

private:
    void work() {
        unsigned long seen = 0;
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(m_mutex);
                m_wake.wait(lock, [&] { return m_stopping || m_generation != seen; });
                if (m_stopping) return;
                seen = m_generation;
            }
            runChunksHere();
        }
    }

    void runChunksHere() {
        t_insideChunk = true;
        int finished = 0;
        for (int c = m_nextChunk.fetch_add(1); c < m_numChunks; c = m_nextChunk.fetch_add(1)) {
            m_chunk(m_context, c);
            ++finished;
        }
        t_insideChunk = false;
        if (finished == 0) return;
        std::lock_guard<std::mutex> lock(m_mutex);
        m_unfinished -= finished;
        if (m_unfinished == 0) m_done.notify_one();
    }

    static thread_local bool t_insideChunk;
    int m_threads = 1;
    std::vector<std::thread> m_workers;
    std::mutex m_busy;   // held by the thread whose loop the pool runs
    std::mutex m_mutex;  // guards the loop's fields and the counts below
    std::condition_variable m_wake, m_done;
    unsigned long m_generation = 0;
    bool m_stopping = false;
    void (*m_chunk)(void*, int) = nullptr;
    void* m_context = nullptr;
    int m_numChunks = 0;
    std::atomic<int> m_nextChunk{0};
    int m_unfinished = 0;
};

thread_local bool HostPool::t_insideChunk = false;

HostPool& pool() {
    static HostPool p;
    return p;
}

}  // namespace

int hostThreads() { return pool().threads(); }

void runChunks(int numChunks, void (*chunk)(void* context, int c), void* context) {
    pool().run(numChunks, chunk, context);
}

}  // namespace btocl
