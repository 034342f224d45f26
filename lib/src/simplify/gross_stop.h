// The gross-error stop of triangle-count levels: a collapse or a part removal that would take the
// level further than a fraction of the bounding-box diagonal from the original is refused, and the
// level keeps the triangles it has (docs/simplify.md, "Gross-error stop"). It refuses only what
// would pass the bound: a level that stays under it is built exactly as without the stop. Private
// to lib/src/simplify.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "collapse_rules.h"

namespace lodbake::simplify_detail {

struct GrossStop {
    double bound = std::numeric_limits<double>::infinity();            // model units; inf = off
    double cheapestRefused = std::numeric_limits<double>::infinity();  // in pass `refusedPass`
    uint32_t refusedPass = 0;  // the last pass that refused a collapse or part (0 = none)

    // The bound of `level`: grossError (a fraction of the diagonal) for a triangle-count level,
    // none for an error target (it sets its own) or when grossError is 0.
    void startLevel(const PlannedLevel& level, double grossError, double diagonal);
    // The largest part size a pruning at `limit` may remove.
    double cap(double limit) const { return limit < bound ? limit : bound; }
    // Whether the collapse (vi -> vj) of cost `dev` keeps the level within the bound: refused when
    // its cost, or near the bound the exact distance of every point it moves (measureAttached),
    // exceeds it; a refusal is remembered for the stop reason.
    bool allows(const CollapseState& s, RuleScratch& w, uint32_t vi, uint32_t vj, double dev, uint32_t pass);
    // Records a part of `size` (model units) that pruning would have removed but for the bound.
    void refusePart(double size, uint32_t pass) { refuse(size, pass); }
    // Whether `pass` refused a collapse or a part: a level stuck after it stopped at the bound.
    bool refusedIn(uint32_t pass) const { return refusedPass == pass && pass != 0; }
    // The stop reason: the smallest refused deviation and the bound, relative to the diagonal.
    std::string reason(double diagonal) const;

private:
    void refuse(double deviation, uint32_t pass);
};

}  // namespace lodbake::simplify_detail
