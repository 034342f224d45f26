// Chart solves under a memory budget (solve_schedule.h).
#include "param/solve_schedule.h"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <list>
#include <mutex>
#include <thread>

#include "lodbake/core/parallel.h"

namespace lodbake::param_detail {

void runWithinBudget(const std::vector<size_t>& order, const std::vector<size_t>& weight, size_t budget, int threads,
                     const std::function<void(size_t)>& fn) {
    const size_t n = std::min<size_t>(size_t(resolveThreads(threads)), order.size());
    if (n <= 1) {
        for (size_t i : order) fn(i);
        return;
    }
    std::mutex m;
    std::condition_variable ended;
    std::list<size_t> pending(order.begin(), order.end());
    size_t runningWeight = 0;
    std::exception_ptr error;
    auto worker = [&]() {
        std::unique_lock<std::mutex> lock(m);
        for (;;) {
            if (error || pending.empty()) return;
            auto it = pending.begin();
            for (; it != pending.end(); ++it) {
                const size_t w = weight[*it];
                if (w == 0 || runningWeight == 0 || runningWeight + w <= budget) break;
            }
            if (it == pending.end()) {
                ended.wait(lock);
                continue;
            }
            const size_t i = *it, w = weight[i];
            pending.erase(it);
            runningWeight += w;
            lock.unlock();
            std::exception_ptr thrown;
            try {
                fn(i);
            } catch (...) {
                thrown = std::current_exception();
            }
            lock.lock();
            runningWeight -= w;
            if (thrown && !error) error = thrown;
            ended.notify_all();
        }
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace lodbake::param_detail
