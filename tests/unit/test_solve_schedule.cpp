// Unit tests for the chart solve schedule under a weight budget (param/solve_schedule.h).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "param/solve_schedule.h"

using namespace lodbake;

TEST(SolveSchedule, EveryItemRunsOnceAndHeavyItemsStayWithinTheBudget) {
    const std::vector<size_t> order{0, 1, 2, 3, 4, 5, 6, 7};
    const std::vector<size_t> weight{90, 60, 50, 0, 0, 40, 0, 10};
    std::vector<std::atomic<int>> runs(order.size());
    std::mutex m;
    size_t running = 0, worst = 0;
    param_detail::runWithinBudget(order, weight, 100, 3, [&](size_t i) {
        {
            std::lock_guard<std::mutex> lock(m);
            running += weight[i];
            worst = std::max(worst, running);
        }
        ++runs[i];
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::lock_guard<std::mutex> lock(m);
        running -= weight[i];
    });
    for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
    EXPECT_LE(worst, 100u);
}

TEST(SolveSchedule, AnItemHeavierThanTheBudgetRunsAloneAndErrorsReachTheCaller) {
    std::atomic<int> ran{0};
    param_detail::runWithinBudget({0, 1}, {500, 500}, 100, 2, [&](size_t) { ++ran; });
    EXPECT_EQ(ran.load(), 2);
    EXPECT_THROW(param_detail::runWithinBudget({0, 1, 2}, {0, 0, 0}, 100, 2,
                                               [&](size_t i) {
                                                   if (i == 1) throw std::runtime_error("x");
                                               }),
                 std::runtime_error);
}
