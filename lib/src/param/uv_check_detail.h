// Private: per-triangle result of the UV injectivity check (uv_check.cpp), used by
// checkUVInjectivity (counts) and by parameterize's level-island fallback (which triangles).
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake::param_detail {

struct UVFolds {
    std::vector<char> flipped;                              // per triangle: signed UV area <= 0 (as float)
    std::vector<std::pair<uint32_t, uint32_t>> overlapping;  // i < j whose interiors intersect, sorted
};

// Same conventions as checkUVInjectivity (glTF UVs rounded to float, flipped triangles not tested
// for overlap). Every overlapping pair is listed (no early out). Rows of the grid on `threads`
// threads (0 = all cores); the result does not depend on the count. `tris` is taken by value (it
// is rounded in place): callers done with theirs move it in rather than hold two copies.
UVFolds findUVFolds(std::vector<std::array<Vec2, 3>> tris, double tolerance, int threads = 1);

}  // namespace lodbake::param_detail
