// Welding by exact position (lodbake/core/weld.h).
#include "lodbake/core/weld.h"

#include <algorithm>

namespace lodbake {
namespace {

// A position's hash for the weld table. Positions read from floats leave the low 29 mantissa bits
// zero, so the words are mixed (MurmurHash3's 64-bit finaliser) before the table's low bits are used.
uint64_t hashOf(const PositionKey& k) {
    uint64_t h = 0;
    for (uint64_t x : k.b) {
        h = (h ^ x) * 0x9e3779b97f4a7c15ull;
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
        h *= 0xc4ceb9fe1a85ec53ull;
        h ^= h >> 33;
    }
    return h;
}

}  // namespace

void PositionWeld::reserve(size_t more) {
    size_t need = 2 * (keys_.size() + more), cap = std::max<size_t>(64, slots_.size());
    while (cap < need) cap *= 2;
    if (cap != slots_.size()) rehash(cap);
    if (keys_.capacity() < keys_.size() + more) keys_.reserve(std::max(keys_.size() + more, 2 * keys_.capacity()));
}

uint32_t PositionWeld::insert(const PositionKey& k, bool& inserted) {
    if (2 * (keys_.size() + 1) > slots_.size()) reserve(std::max<size_t>(keys_.size(), 32));
    const size_t mask = slots_.size() - 1;
    for (size_t i = size_t(hashOf(k)) & mask;; i = (i + 1) & mask) {
        const uint32_t id = slots_[i];
        if (id == kEmpty) {
            slots_[i] = uint32_t(keys_.size());
            keys_.push_back(k);
            inserted = true;
            return slots_[i];
        }
        if (keys_[id] == k) {
            inserted = false;
            return id;
        }
    }
}

void PositionWeld::prefetch(const PositionKey& k) const {
    if (!slots_.empty()) __builtin_prefetch(&slots_[size_t(hashOf(k)) & (slots_.size() - 1)]);
}

void PositionWeld::rehash(size_t cap) {
    slots_.assign(cap, kEmpty);
    for (uint32_t id = 0; id < keys_.size(); ++id)
        for (size_t i = size_t(hashOf(keys_[id])) & (cap - 1);; i = (i + 1) & (cap - 1))
            if (slots_[i] == kEmpty) {
                slots_[i] = id;
                break;
            }
}

}  // namespace lodbake
