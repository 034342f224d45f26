// A deterministic parallel-for over [0, count), used by compare's metrics and parameterize's charts.
// Work is split into fixed chunks independent of the thread count; callers write results into
// per-index slots and reduce them in index order, so figures never depend on `threads`.
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

// Calls fn(i) for every i in [0, count), on up to `threads` threads. The first exception thrown by
// a worker is rethrown on the calling thread.
inline void parallelFor(size_t count, int threads, const std::function<void(size_t)>& fn) {
    int n = std::min<size_t>(static_cast<size_t>(resolveThreads(threads)), count);
    if (n <= 1) {
        for (size_t i = 0; i < count; ++i) fn(i);
        return;
    }
    std::atomic<size_t> next{0};
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    auto worker = [&] {
        for (;;) {
            size_t i = next.fetch_add(1);
            if (i >= count || failed.load()) return;
            try {
                fn(i);
            } catch (...) {
                if (!failed.exchange(true)) error = std::current_exception();
                return;
            }
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace lodbake
