// The gross-error stop of triangle-count levels (gross_stop.h, docs/simplify.md).

#include "gross_stop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lodbake::simplify_detail {

// A collapse whose cost is above this fraction of the bound is also measured exactly: the cost
// looks at v_i's own attached points, the exact measure at those of every vertex whose fan changes.
constexpr double kExactFraction = 0.5;

void GrossStop::startLevel(const PlannedLevel& level, double grossError, double diagonal) {
    bound = (grossError > 0 && !level.hasErrorTarget()) ? grossError * diagonal : std::numeric_limits<double>::infinity();
    cheapestRefused = std::numeric_limits<double>::infinity();
    refusedPass = 0;
}

bool GrossStop::allows(const CollapseState& s, RuleScratch& w, uint32_t vi, uint32_t vj, double dev, uint32_t pass) {
    if (!(dev > kExactFraction * bound)) return true;
    const double d = dev > bound ? dev : std::max(dev, measureAttached(s, w, vi, vj));
    if (d <= bound) return true;
    refuse(d, pass);
    return false;
}

void GrossStop::refuse(double deviation, uint32_t pass) {
    if (refusedPass != pass) cheapestRefused = std::numeric_limits<double>::infinity();
    refusedPass = pass;
    cheapestRefused = std::min(cheapestRefused, deviation);
}

std::string GrossStop::reason(double diagonal) const {
    const double scale = diagonal > 0 ? diagonal : 1;
    char buf[160];
    std::snprintf(buf, sizeof buf, "gross error: the cheapest collapse or part removal left deviates %.3g of the diagonal, over the bound %.3g",
                  cheapestRefused / scale, bound / scale);
    return buf;
}

}  // namespace lodbake::simplify_detail
