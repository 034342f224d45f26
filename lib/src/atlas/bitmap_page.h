// The page of packAtlas as one bit per texel, with per-row free counts and longest free runs: the
// lowest free position of a chart footprint (bottom-left fill), and placing it. The unions of
// 2, 4, 8... consecutive rows (a sparse table) test each of a footprint's blocks against its rows
// at once.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "atlas/chart_footprint.h"

namespace lodbake::atlas_detail {

// The page as one bit per texel; charts are placed where their footprint meets no set bit.
class BitmapPage {
public:
    BitmapPage(int width, int height)
        : W_(width), H_(height), words_((size_t(width) + 63) / 64), bits_(words_ * size_t(height), 0),
          unions_(kUnionLevels * words_ * size_t(height), 0), rowFree_(size_t(height), width), rowRun_(size_t(height), width) {}

    // The lowest position (smallest y + key, then smallest x) with y + key below `limit`.
    bool find(const Footprint& f, double key, double limit, int& outX, int& outY) const {
        int fullRow = -1;
        for (int y = 0; y + f.h <= H_ && y + key < limit; ++y) {
            // A row needs as many free texels as the footprint's row, and a free run as long as
            // its longest run (fragmented rows low on the page fail here). A page row short of
            // the footprint's least row rules out every position that covers it: the search
            // resumes above it (rows are tested top first, so the jump is the longest).
            // The page row that failed last is tested first: it usually fails the next position too.
            auto tooFull = [&](int i) {
                const int free = rowFree_[size_t(y + i)], run = rowRun_[size_t(y + i)];
                if (free >= f.rowCells[size_t(i)] && run >= f.rowLongest[size_t(i)]) return false;
                fullRow = y + i;
                if (free < f.leastCells || run < f.leastLongest) y += i;
                return true;
            };
            if (fullRow >= y && tooFull(fullRow - y)) continue;
            bool roomy = true;
            for (int i = f.h - 1; i >= 0 && roomy; --i) roomy = !tooFull(i);
            if (!roomy) continue;
            // The footprint's blocks (Footprint::blocks), each against the union of its rows: a set
            // texel there meets the footprint. Large blocks first: they collide most often, and on
            // a union of rows the set stretches, and so the jumps, are longest. The block that
            // collided last is tested first (it usually meets the next position too).
            int x = 0;
            size_t hot = 0;
            while (x + f.w <= W_) {
                int next = -1;
                // Every shift that keeps the block over the first set texel p it meets, or starts
                // it inside the set stretch from p, collides: it starts at the stretch's end at least.
                auto collides = [&](const Footprint::Block& k) {
                    const Rows rows{level(k.level, y + k.top), level(k.level, y + k.top + k.rows - (1 << k.level))};
                    const int p = firstSet(rows, x + k.a, x + k.b);
                    if (p >= 0) next = std::max(x + 1, firstClear(rows, p) - k.a);
                    return p >= 0;
                };
                if (!f.blocks.empty() && !collides(f.blocks[hot]))
                    for (size_t k = 0; k < f.blocks.size(); ++k)
                        if (k != hot && collides(f.blocks[k])) {
                            hot = k;
                            break;
                        }
                if (next < 0) { outX = x; outY = y; return true; }
                x = next;
            }
        }
        return false;
    }

    // Whether the footprint lies on the page at (x, y).
    bool onPage(const Footprint& f, int x, int y) const { return x >= 0 && y >= 0 && x + f.w <= W_ && y + f.h <= H_; }

    void place(const Footprint& f, int x, int y) {
        for (int i = 0; i < f.h; ++i)
            for (const auto& [a, b] : f.rows[size_t(i)]) {
                uint64_t* row = bits_.data() + size_t(y + i) * words_;
                const int lo = x + a, hi = x + b;
                for (int w = lo / 64; w <= hi / 64; ++w) {
                    uint64_t m = ~uint64_t(0);
                    if (w == lo / 64) m &= ~uint64_t(0) << (lo % 64);
                    if (w == hi / 64 && hi % 64 != 63) m &= (uint64_t(1) << (hi % 64 + 1)) - 1;
                    row[w] |= m;
                }
            }
        for (int i = 0; i < f.h; ++i) {
            rowFree_[size_t(y + i)] = W_ - setCells(y + i);  // kept charts may overlap
            rowRun_[size_t(y + i)] = longestFreeRun(y + i);
        }
        // The unions of 2^k rows from s that include a changed row, each from two of half as many,
        // over the words the footprint's columns touch.
        const size_t w0 = size_t(std::max(0, x)) / 64, w1 = std::min(words_ - 1, size_t(std::max(0, x + f.w - 1)) / 64);
        for (int k = 1; k <= kUnionLevels; ++k) {
            const int n = 1 << k, half = n / 2;
            for (int s = std::max(0, y - n + 1); s <= std::min(H_ - n, y + f.h - 1); ++s) {
                uint64_t* out = unions_.data() + unionAt(k, s);
                const uint64_t* lo = level(k - 1, s);
                const uint64_t* hi = level(k - 1, s + half);
                for (size_t w = w0; w <= w1; ++w) out[w] = lo[w] | hi[w];
            }
        }
        usedW_ = std::max(usedW_, x + f.w);
        usedH_ = std::max(usedH_, y + f.h);
    }
    int usedWidth() const { return usedW_; }
    int usedHeight() const { return usedH_; }
    int height() const { return H_; }

private:
    // Union levels kept: 2^1 ... 2^kUnionLevels rows, enough for any block (kBlockRows rows).
    static constexpr int kUnionLevels = [] {
        int k = 0;
        while ((2 << k) <= kBlockRows) ++k;
        return k;
    }();
    // One row of the page, or the union of two (of 2^k rows each, which may overlap): a texel is
    // set when it is set in either.
    struct Rows {
        const uint64_t* a = nullptr;
        const uint64_t* b = nullptr;
    };

    int W_, H_;
    size_t words_;
    std::vector<uint64_t> bits_;
    std::vector<uint64_t> unions_;  // level k (1...kUnionLevels), row s: the union of rows [s, s + 2^k)
    std::vector<int> rowFree_;
    std::vector<int> rowRun_;  // longest run of free texels per row
    int usedW_ = 0, usedH_ = 0;

    // Level k >= 1 of the unions at row s, in unions_.
    size_t unionAt(int k, int s) const { return (size_t(k - 1) * size_t(H_) + size_t(s)) * words_; }
    // Row s (k = 0), or the union of rows [s, s + 2^k).
    const uint64_t* level(int k, int s) const { return k == 0 ? bits_.data() + size_t(s) * words_ : unions_.data() + unionAt(k, s); }

    int setCells(int y) const {
        const uint64_t* row = bits_.data() + size_t(y) * words_;
        int n = 0;
        for (size_t w = 0; w < words_; ++w) n += __builtin_popcountll(row[w]);
        return n;
    }

    int longestFreeRun(int y) const {
        const uint64_t* row = bits_.data() + size_t(y) * words_;
        int best = 0, run = 0;
        for (size_t w = 0; w < words_; ++w) {
            uint64_t m = row[w];
            const int n = w + 1 == words_ && W_ % 64 ? W_ % 64 : 64;  // texels of the page in this word
            if (n < 64) m |= ~uint64_t(0) << n;
            // Alternate over the word: a free stretch (ends the run), then a set stretch.
            for (int pos = 0; pos < 64;) {
                const uint64_t rest = m >> pos;
                if (rest == 0) { run += 64 - pos; break; }
                const int free = __builtin_ctzll(rest);
                best = std::max(best, run + free);
                run = 0;
                pos += free;
                const uint64_t clear = ~(m >> pos);  // the bits shifted in count as clear
                if (clear == 0) break;
                pos += __builtin_ctzll(clear);
            }
        }
        return std::max(best, run);
    }

    // The first clear bit at or after a in the rows (the page's width when there is none).
    int firstClear(Rows r, int a) const {
        for (size_t w = size_t(a) / 64; w < words_; ++w) {
            uint64_t m = ~(r.a[w] | r.b[w]);
            if (w == size_t(a) / 64) m &= ~uint64_t(0) << (a % 64);
            if (m) return std::min(W_, int(w * 64) + __builtin_ctzll(m));
        }
        return W_;
    }

    // The first set bit in [a, b] of the rows, or -1.
    int firstSet(Rows r, int a, int b) const {
        for (int w = a / 64; w <= b / 64; ++w) {
            uint64_t m = r.a[w] | r.b[w];
            if (w == a / 64) m &= ~uint64_t(0) << (a % 64);
            if (w == b / 64 && b % 64 != 63) m &= (uint64_t(1) << (b % 64 + 1)) - 1;
            if (m) return w * 64 + __builtin_ctzll(m);
        }
        return -1;
    }
};

}  // namespace lodbake::atlas_detail
