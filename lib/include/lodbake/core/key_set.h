// A set of 64-bit keys (edge keys, (vertex, chart) pairs) for the membership tests of mesh sweeps:
// one open-addressing table with linear probing, so a million half-edges cost one flat array
// instead of an allocation each. It answers membership only and has no iteration, so nothing can
// depend on its hash order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodbake {

class KeySet {
public:
    // Room for `expected` keys before the table grows (it is kept at most half full).
    explicit KeySet(size_t expected = 0) { reset(slotsFor(expected)); }

    // Adds `key`; true when it was not in the set.
    bool insert(uint64_t key) {
        if (key == kEmpty) {
            if (hasEmpty_) return false;
            hasEmpty_ = true;
            ++size_;
            return true;
        }
        if (2 * (size_ + 1) > slots_.size()) grow();
        for (size_t i = slot(key);; i = (i + 1) & mask_) {
            if (slots_[i] == key) return false;
            if (slots_[i] == kEmpty) {
                slots_[i] = key;
                ++size_;
                return true;
            }
        }
    }

    bool contains(uint64_t key) const {
        if (key == kEmpty) return hasEmpty_;
        for (size_t i = slot(key);; i = (i + 1) & mask_) {
            if (slots_[i] == key) return true;
            if (slots_[i] == kEmpty) return false;
        }
    }

    size_t size() const { return size_; }

private:
    static constexpr uint64_t kEmpty = ~uint64_t(0);  // marks a free slot; the key itself is a flag

    static size_t slotsFor(size_t keys) {
        size_t n = 16;
        while (n < 2 * keys) n *= 2;
        return n;
    }
    void reset(size_t slots) {
        slots_.assign(slots, kEmpty);
        mask_ = slots - 1;
        shift_ = 64;
        for (size_t s = slots; s > 1; s /= 2) --shift_;
    }
    // Fibonacci hashing: the product's top bits depend on every bit of the key.
    size_t slot(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
    void grow() {
        std::vector<uint64_t> old;
        old.swap(slots_);
        reset(2 * old.size());
        for (uint64_t k : old)
            if (k != kEmpty)
                for (size_t i = slot(k);; i = (i + 1) & mask_)
                    if (slots_[i] == kEmpty) { slots_[i] = k; break; }
    }

    std::vector<uint64_t> slots_;
    size_t mask_ = 0;
    int shift_ = 64;
    size_t size_ = 0;
    bool hasEmpty_ = false;
};

}  // namespace lodbake
