// Deterministic parallel loops over [0, count), used by compare's metrics, parameterize's charts and
// simplify's candidate evaluation. Work is split into items (or fixed chunks) independent of the
// thread count; callers write results into per-item slots and reduce them in index order, so figures
// never depend on `threads`.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace lodbake {

inline int resolveThreads(int threads) {
    if (threads > 0) return threads;
    unsigned h = std::thread::hardware_concurrency();
    return h == 0 ? 1 : static_cast<int>(h);
}

namespace parallel_detail {

// Calls task(k, thread) for every k in [0, tasks) on up to `threads` threads (thread 0 is the
// caller), each task once, in any order. The first exception thrown by a task is rethrown on the
// calling thread; no new task starts after it.
inline void runTasks(size_t tasks, int threads, const std::function<void(size_t, size_t)>& task) {
    size_t n = std::min<size_t>(static_cast<size_t>(resolveThreads(threads)), tasks);
    if (n <= 1) {
        for (size_t k = 0; k < tasks; ++k) task(k, 0);
        return;
    }
    std::atomic<size_t> next{0};
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    auto worker = [&](size_t thread) {
        for (;;) {
            size_t k = next.fetch_add(1);
            if (k >= tasks || failed.load()) return;
            try {
                task(k, thread);
            } catch (...) {
                if (!failed.exchange(true)) error = std::current_exception();
                return;
            }
        }
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < n; ++t) pool.emplace_back(worker, t);
    worker(0);
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace parallel_detail

// Calls fn(i) for every i in [0, count), on up to `threads` threads (0 = all cores). The first
// exception thrown by a worker is rethrown on the calling thread.
inline void parallelFor(size_t count, int threads, const std::function<void(size_t)>& fn) {
    parallel_detail::runTasks(count, threads, [&](size_t i, size_t) { fn(i); });
}

// The number of chunks parallelChunks splits [0, count) into.
inline size_t chunkCount(size_t count, size_t chunk) { return (count + chunk - 1) / chunk; }

// Calls fn(begin, end, thread) for every chunk [c * chunk, min(count, (c + 1) * chunk)) of
// [0, count), on up to `threads` threads (0 = all cores). `thread` is below resolveThreads(threads)
// and selects the caller's per-thread scratch; chunk c = begin / chunk selects its result slot. The
// chunks do not depend on the thread count, so reducing the slots in order gives the same result for
// any `threads`. Exceptions as parallelFor.
inline void parallelChunks(size_t count, size_t chunk, int threads,
                           const std::function<void(size_t, size_t, size_t)>& fn) {
    parallel_detail::runTasks(chunkCount(count, chunk), threads, [&](size_t c, size_t thread) {
        fn(c * chunk, std::min(count, (c + 1) * chunk), thread);
    });
}

}  // namespace lodbake
