// Welding by exact position: points at the same position (bit for bit, -0 and +0 alike) share one
// vertex id, handed out in order of first appearance. Used by the glTF reader to weld the
// primitives of a scene into one mesh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

// A position as the bits of its three coordinates (-0 stored as +0): equal keys, equal positions.
struct PositionKey {
    uint64_t b[3];
    bool operator==(const PositionKey& o) const { return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2]; }
};

inline PositionKey positionKey(Vec3 p) {
    PositionKey k;
    double v[3] = {p.x + 0.0, p.y + 0.0, p.z + 0.0};  // + 0.0 turns -0 into +0
    for (int i = 0; i < 3; ++i) std::memcpy(&k.b[i], &v[i], 8);
    return k;
}

// The weld table: an open-addressing hash table (linear probing) of vertex ids, id = the number
// of distinct positions inserted before it.
class PositionWeld {
public:
    // Room for `more` new positions without rehashing (geometric growth: many small primitives
    // stay linear).
    void reserve(size_t more);
    // The id of `k`; a new key gets the next id (`inserted` is then true).
    uint32_t insert(const PositionKey& k, bool& inserted);
    // Asks the memory for the slot where k's search starts, some inserts ahead of k's: on a table
    // of millions of positions each insert otherwise waits for a cache miss.
    void prefetch(const PositionKey& k) const;

private:
    static constexpr uint32_t kEmpty = ~0u;
    std::vector<uint32_t> slots_;
    std::vector<PositionKey> keys_;

    void rehash(size_t cap);
};

}  // namespace lodbake
