// The order chart solves run in on several threads (parameterize step 3): largest first, as many
// at once as there are threads, except that the largest LSCM factorisations (the run's memory
// peak: a 140k-vertex chart's supernodal factor and normal equations are some 400 MB) do not run
// side by side past a vertex budget; the other threads take smaller charts meanwhile.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace lodbake::param_detail {

// Together, the charts solved at once hold at most this many vertices of charts that keep their
// LSCM map without a Ceres solve (more than kKeepLscmAboveVertices vertices: all their memory is
// the factorisation); a single heavier chart runs with no other such chart.
constexpr size_t kLscmVerticesTogether = 100000;

// Calls fn(i) once for every i of `order`, on up to `threads` threads (0 = all cores; the caller
// is one of them). A thread takes the first item of `order` not yet started whose weight, added
// to the weights running, stays within `budget` (or that runs alone); when none fits it waits
// for one to end. Weight 0 always fits. The first exception thrown by fn is rethrown on the
// calling thread once the running items end; no item starts after it.
void runWithinBudget(const std::vector<size_t>& order, const std::vector<size_t>& weight, size_t budget, int threads,
                     const std::function<void(size_t)>& fn);

}  // namespace lodbake::param_detail
