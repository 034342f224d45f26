// Shapes of candidate merges, memoised (chart/charts.cpp): the Shape SetMeasurer gives a face set,
// and ShapeMemo, which keys those of candidate merges by their faces' vertex triples.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake::chart_detail {

// Shape of a face set: E_region and the normal cone, plus the disk test.
struct Shape {
    bool disk = false;
    bool overLimits = false;  // the shape exceeds the ShapeLimits given: the disk test was not run
    double energy = 0;        // E_region with lengths relative to the diagonal
    double coneDegrees = 0;
};

// Shapes of candidate merges keyed by their faces' vertex triples in face order, which is all
// SetMeasurer::measure reads: a mesh of coincident copies of one part (instances sharing their
// vertices) proposes the same triple sequence for many pairs of charts, and each is measured once.
// Only worth its keys when most faces repeat another face's triple (see ShapeMemo::worthwhile).
class ShapeMemo {
public:
    // Face class: the smallest face with the same (ordered) vertex triple.
    explicit ShapeMemo(const TriMesh& mesh) : faceClass_(mesh.triangleCount()) {
        std::vector<uint32_t> byTriple(faceClass_.size());
        for (uint32_t f = 0; f < byTriple.size(); ++f) byTriple[f] = f;
        std::sort(byTriple.begin(), byTriple.end(), [&](uint32_t a, uint32_t b) {
            return mesh.triangles[a] != mesh.triangles[b] ? mesh.triangles[a] < mesh.triangles[b] : a < b;
        });
        for (size_t i = 0; i < byTriple.size(); ++i) {
            const bool repeat = i > 0 && mesh.triangles[byTriple[i]] == mesh.triangles[byTriple[i - 1]];
            faceClass_[byTriple[i]] = repeat ? faceClass_[byTriple[i - 1]] : byTriple[i];
            classes_ += repeat ? 0 : 1;
        }
    }
    bool worthwhile() const { return classes_ * 2 <= faceClass_.size(); }

    // The memoised shape of the union of two disjoint sorted face lists (the faces of a candidate
    // merge), measuring it on the first request: measure() builds the union itself, so a shape met
    // before (most of them, on a mesh of copies) costs one pass over the two lists and one probe.
    template <class MeasureFn>
    Shape shape(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b, MeasureFn&& measure) {
        // The key (the union's face classes in face order) and its hash, in one merge.
        const size_t n = a.size() + b.size();
        key_.resize(n);
        uint64_t h = 0x9E3779B97F4A7C15ull ^ n;
        size_t i = 0, j = 0, k = 0;
        for (; i < a.size() && j < b.size(); ++k) {
            const uint32_t c = faceClass_[b[j] < a[i] ? b[j++] : a[i++]];
            key_[k] = c;
            h = (h ^ c) * 0xFF51AFD7ED558CCDull;
        }
        for (; i < a.size(); ++i, ++k) key_[k] = faceClass_[a[i]], h = (h ^ key_[k]) * 0xFF51AFD7ED558CCDull;
        for (; j < b.size(); ++j, ++k) key_[k] = faceClass_[b[j]], h = (h ^ key_[k]) * 0xFF51AFD7ED558CCDull;
        h ^= h >> 32;
        if (slots_.empty()) slots_.assign(1024, Slot{});
        const size_t mask = slots_.size() - 1;
        for (size_t s = size_t(h) & mask;; s = (s + 1) & mask) {
            Slot& slot = slots_[s];
            if (slot.length == kEmpty) break;
            if (slot.hash == h && slot.length == n && std::equal(key_.begin(), key_.end(), keys_.begin() + std::ptrdiff_t(slot.start)))
                return slot.shape;
        }
        const Shape measured = measure();
        insert({h, keys_.size(), uint32_t(n), measured});
        keys_.insert(keys_.end(), key_.begin(), key_.end());
        return measured;
    }
    void clear() {
        std::vector<Slot>().swap(slots_);
        std::vector<uint32_t>().swap(keys_);
        used_ = 0;
    }

private:
    static constexpr uint32_t kEmpty = UINT32_MAX;
    // An open-addressed table of the shapes measured (linear probing, at most half full); the keys
    // sit one after another in keys_.
    struct Slot {
        uint64_t hash = 0;
        size_t start = 0;  // of the key in keys_
        uint32_t length = kEmpty;
        Shape shape;
    };
    void insert(const Slot& e) {
        if (2 * (used_ + 1) > slots_.size()) {
            std::vector<Slot> old(slots_.size() * 2);
            old.swap(slots_);
            used_ = 0;
            for (const Slot& o : old)
                if (o.length != kEmpty) insert(o);
        }
        const size_t mask = slots_.size() - 1;
        size_t s = size_t(e.hash) & mask;
        while (slots_[s].length != kEmpty) s = (s + 1) & mask;
        slots_[s] = e;
        ++used_;
    }
    std::vector<uint32_t> faceClass_, key_;
    size_t classes_ = 0;
    std::vector<Slot> slots_;
    std::vector<uint32_t> keys_;
    size_t used_ = 0;
};

}  // namespace lodbake::chart_detail
