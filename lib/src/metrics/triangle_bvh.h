// Closest points on a set of CGAL triangles (private to cgal_distance.cpp, the one translation unit
// that includes CGAL): a bounding volume hierarchy of float boxes, searched nearest box first.
//
// The answer is canonical: of the points CGAL's Construct_projected_point_3 gives for the
// triangles, the one at the least squared distance from the query, ties going to the triangle of
// the highest rank (setTieRanks). Boxes only prune triangles certainly farther than the best point
// found (each box is widened by 1e-9 of the coordinates' scale, far beyond the rounding of a
// projection), so the answer does not depend on the tree's shape, the visiting order, a starting
// bound or the thread count. A triangle's plane prunes it too when it is well shaped (its unit
// normal then holds to far below the widening): no point of it lies nearer than its plane. Ranked
// in the order CGAL's AABB tree visits the triangles, it is that tree's closest_point (the last of
// equally close points it visits); they could differ only where CGAL's search keeps its starting
// hint or skips a box by a rounding error.
//
// The tree reads the caller's triangles where they are (a million CGAL triangles are 78 MB): the
// vector it is built from must outlive it and keep its elements (moving the vector keeps them).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <CGAL/Simple_cartesian.h>

#include "lodbake/core/parallel.h"

namespace lodbake::distance_detail {

class TriangleBvh {
public:
    using Kernel = CGAL::Simple_cartesian<double>;
    using Point = Kernel::Point_3;
    using Triangle = Kernel::Triangle_3;

    TriangleBvh() = default;
    // `threads` build the subtrees below the top levels side by side (the tree is the same for any
    // count).
    explicit TriangleBvh(const std::vector<Triangle>& triangles, int threads = 1) : list_(triangles.data()) {
        build(triangles, threads);
    }

    bool empty() const { return input_.empty(); }

    // Which of equally close points closest() returns: the one of the triangle with the highest
    // rank (rank[i] for input triangle i; by default i itself).
    void setTieRanks(const std::vector<uint32_t>& rank) {
        for (size_t k = 0; k < input_.size(); ++k) tieRank_[k] = rank[input_[k]];
    }

    // The closest point to q (the tree must hold a triangle). `bound2` (optional) is a squared distance that some point of the
    // triangles is known to lie within (a nearby query's answer, measured from q): it only prunes.
    // `near` (optional, in and out) names a triangle in the tree's own numbering whose point nearest
    // q bounds the search too (a nearby query's answer lies on it: q's point on it is mostly the
    // answer, a far tighter bound than that answer itself); on return it names the answer's.
    Point closest(const Point& q, double bound2 = std::numeric_limits<double>::infinity(), uint32_t* near = nullptr) const {
        Point best(0, 0, 0);
        uint32_t at = 0;
        if (near && *near < input_.size())
            bound2 = std::min(bound2, CGAL::squared_distance(q, Kernel().construct_projected_point_3_object()(triangle(*near), q)));
        // The bound widened past rounding: the point it came from is no projection of q.
        if (!search(q, bound2 * (1 + 1e-9) + tiny2_, best, at)) search(q, std::numeric_limits<double>::infinity(), best, at);
        if (near) *near = at;
        return best;
    }

private:
    // Triangle t of the leaf order.
    const Triangle& triangle(uint32_t t) const { return list_[input_[t]]; }

    struct Box {
        std::array<float, 3> lo, hi;
    };
    struct Node {
        Box box;
        uint32_t first = 0;  // leaf: its first triangle; inner: its second child (the first follows it)
        uint32_t count = 0;  // leaf: its triangles; inner: 0
    };
    static constexpr uint32_t kLeaf = 4;
    static constexpr int kBins = 16;
    // Below this depth median splits: the search's stack (64) outlasts kSahDepth + log2 of any count.
    static constexpr int kSahDepth = 28;
    // The build splits the top kTopDepth levels first (ranges above kTopMin triangles); the subtrees
    // below them are the tasks the threads share.
    static constexpr int kTopDepth = 4;
    static constexpr uint32_t kTopMin = 8192;

    const Triangle* list_ = nullptr;   // the caller's triangles, in input order
    std::vector<Box> boxes_;           // each triangle's widened box
    struct Plane {
        std::array<double, 3> normal{};  // unit; zero for a sliver (its plane prunes nothing)
        std::array<double, 3> corner{};
    };
    std::vector<Plane> planes_;        // each triangle's plane
    double widen_ = 0;                 // the boxes' widening
    std::vector<uint32_t> input_;      // each triangle's index in the input
    std::vector<uint32_t> tieRank_;    // of equally close points, the one of the highest rank wins
    std::vector<Node> nodes_;
    double tiny2_ = 0;                 // squared widening

    // Lower bound of the squared distance from q to anything inside box b.
    static double boxDistance2(const Box& b, const Point& q) {
        double d2 = 0;
        const double p[3] = {q.x(), q.y(), q.z()};
        for (int a = 0; a < 3; ++a) {
            const double lo = double(b.lo[size_t(a)]), hi = double(b.hi[size_t(a)]);
            const double e = p[a] < lo ? lo - p[a] : (p[a] > hi ? p[a] - hi : 0.0);
            d2 += e * e;
        }
        return d2;
    }

    // Whether every point of the triangle lies farther than best2 from q, by its plane: the
    // distance to the plane less a slack far past the rounding of the normal (a relative error
    // below 1e-12 for a triangle whose sine exceeds 1e-4), of the product and of a projection.
    bool beyondPlane(const Plane& pl, const Point& q, double best2) const {
        const double d[3] = {q.x() - pl.corner[0], q.y() - pl.corner[1], q.z() - pl.corner[2]};
        const double along = pl.normal[0] * d[0] + pl.normal[1] * d[1] + pl.normal[2] * d[2];
        const double lower = std::abs(along) - widen_ - 1e-9 * (std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]));
        return lower > 0 && lower * lower > best2;
    }

    bool search(const Point& q, double limit2, Point& best, uint32_t& at) const {
        bool found = false;
        double best2 = limit2;
        uint32_t bestRank = 0;
        uint32_t stack[64];  // the depth is below kSahDepth + log2 of the triangle count
        double stackD2[64];
        int top = 0;
        uint32_t node = 0;
        double nodeD2 = boxDistance2(nodes_[0].box, q);
        for (;;) {
            if (nodeD2 <= best2) {  // else farther than the best point: nothing in it can win
                const Node& n = nodes_[node];
                if (n.count > 0) {
                    for (uint32_t t = n.first; t < n.first + n.count; ++t) {
                        if (boxDistance2(boxes_[t], q) > best2 || beyondPlane(planes_[t], q, best2)) continue;
                        const Point p = Kernel().construct_projected_point_3_object()(triangle(t), q);
                        const double d2 = CGAL::squared_distance(q, p);
                        if (d2 < best2 || (d2 == best2 && (!found || tieRank_[t] > bestRank))) {
                            best2 = d2;
                            best = p;
                            bestRank = tieRank_[t];
                            at = t;
                            found = true;
                        }
                    }
                } else {
                    const uint32_t a = node + 1, b = n.first;
                    const double da = boxDistance2(nodes_[a].box, q), db = boxDistance2(nodes_[b].box, q);
                    const bool aFirst = da <= db;
                    stack[top] = aFirst ? b : a;
                    stackD2[top++] = aFirst ? db : da;
                    node = aFirst ? a : b;
                    nodeD2 = aFirst ? da : db;
                    continue;
                }
            }
            if (top == 0) break;
            --top;
            node = stack[top];
            nodeD2 = stackD2[top];
        }
        return found;
    }

    static Plane planeOf(const Triangle& tr) {
        Plane pl;
        double e1[3], e2[3];
        for (int a = 0; a < 3; ++a) {
            pl.corner[size_t(a)] = tr.vertex(0)[a];
            e1[a] = tr.vertex(1)[a] - tr.vertex(0)[a];
            e2[a] = tr.vertex(2)[a] - tr.vertex(0)[a];
        }
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        const double l2 = std::sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
        if (!(len > 1e-4 * l1 * l2) || !std::isfinite(len)) return pl;
        for (size_t a = 0; a < 3; ++a) pl.normal[a] = n[a] / len;
        return pl;
    }

    // The surface area heuristic's split of order[begin, end) (centres' box c): the bin boundary
    // along an axis of least area x count summed over both sides, order partitioned there (stable:
    // deterministic). Returns its position, or begin when no boundary has centres on both sides.
    static uint32_t sahSplit(std::vector<uint32_t>& order, uint32_t begin, uint32_t end, const std::vector<std::array<double, 6>>& box,
                             const std::vector<std::array<double, 3>>& centre, const std::array<double, 6>& c) {
        auto area = [](const std::array<double, 6>& b) {
            const double x = b[3] - b[0], y = b[4] - b[1], z = b[5] - b[2];
            return x * y + y * z + z * x;
        };
        const std::array<double, 6> none{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
        auto grow = [](std::array<double, 6>& b, const std::array<double, 6>& o) {
            for (size_t a = 0; a < 3; ++a) {
                b[a] = std::min(b[a], o[a]);
                b[a + 3] = std::max(b[a + 3], o[a + 3]);
            }
        };
        double bestCost = std::numeric_limits<double>::infinity();
        size_t bestAxis = 0;
        int bestBin = 0;
        auto binOf = [&](uint32_t t, size_t a) {
            const double extent = c[a + 3] - c[a];
            return std::min(kBins - 1, int(double(kBins) * (centre[t][a] - c[a]) / extent));
        };
        for (size_t a = 0; a < 3; ++a) {
            if (!(c[a + 3] - c[a] > 0)) continue;
            std::array<std::array<double, 6>, kBins> bins;
            bins.fill(none);
            std::array<uint32_t, kBins> count{};
            for (uint32_t i = begin; i < end; ++i) {
                const int k = binOf(order[i], a);
                grow(bins[size_t(k)], box[order[i]]);
                ++count[size_t(k)];
            }
            std::array<double, kBins> rightCost{};
            std::array<double, 6> acc = none;
            uint32_t n = 0;
            for (int k = kBins - 1; k > 0; --k) {
                grow(acc, bins[size_t(k)]);
                n += count[size_t(k)];
                rightCost[size_t(k)] = n ? area(acc) * n : 0;
            }
            acc = none;
            n = 0;
            for (int k = 1; k < kBins; ++k) {  // boundary before bin k
                grow(acc, bins[size_t(k - 1)]);
                n += count[size_t(k - 1)];
                if (n == 0 || n == end - begin) continue;
                const double cost = area(acc) * n + rightCost[size_t(k)];
                if (cost < bestCost) bestCost = cost, bestAxis = a, bestBin = k;
            }
        }
        if (bestCost == std::numeric_limits<double>::infinity()) return begin;
        const auto split = std::stable_partition(order.begin() + begin, order.begin() + end,
                                                 [&](uint32_t t) { return binOf(t, bestAxis) < bestBin; });
        return uint32_t(split - order.begin());
    }

    void build(const std::vector<Triangle>& triangles, int threads) {
        const size_t n = triangles.size();
        if (n == 0) return;
        std::vector<std::array<double, 6>> box(n);
        std::vector<std::array<double, 3>> centre(n);
        constexpr size_t kChunk = 65536;  // triangles per task of the per-triangle loops
        std::vector<double> chunkScale(chunkCount(n, kChunk), 0);
        parallelChunks(n, kChunk, threads, [&](size_t begin, size_t end, size_t) {
            double scale = 0;
            for (size_t t = begin; t < end; ++t) {
                std::array<double, 6> b{};
                for (int a = 0; a < 3; ++a) {
                    const double x = triangles[t].vertex(0)[a], y = triangles[t].vertex(1)[a], z = triangles[t].vertex(2)[a];
                    b[size_t(a)] = std::min({x, y, z});
                    b[size_t(a) + 3] = std::max({x, y, z});
                    centre[t][size_t(a)] = 0.5 * (b[size_t(a)] + b[size_t(a) + 3]);
                    scale = std::max({scale, std::abs(b[size_t(a)]), std::abs(b[size_t(a) + 3])});
                }
                box[t] = b;
            }
            chunkScale[begin / kChunk] = scale;
        });
        const double scale = *std::max_element(chunkScale.begin(), chunkScale.end());
        const double widen = 1e-9 * scale;
        tiny2_ = widen * widen;
        widen_ = widen;
        auto toBox = [&](const std::array<double, 6>& b) {
            Box f;
            for (size_t a = 0; a < 3; ++a) {
                f.lo[a] = std::nextafter(float(b[a] - widen), -std::numeric_limits<float>::infinity());
                f.hi[a] = std::nextafter(float(b[a + 3] + widen), std::numeric_limits<float>::infinity());
            }
            return f;
        };
        std::vector<uint32_t> order(n);
        for (uint32_t t = 0; t < n; ++t) order[t] = t;
        // The triangles' box and their centres' box of order[begin, end).
        auto bounds = [&](uint32_t begin, uint32_t end, std::array<double, 6>& b, std::array<double, 6>& c) {
            b = {1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
            c = b;
            for (uint32_t i = begin; i < end; ++i) {
                const uint32_t t = order[i];
                for (size_t a = 0; a < 3; ++a) {
                    b[a] = std::min(b[a], box[t][a]);
                    b[a + 3] = std::max(b[a + 3], box[t][a + 3]);
                    c[a] = std::min(c[a], centre[t][a]);
                    c[a + 3] = std::max(c[a + 3], centre[t][a]);
                }
            }
        };
        // Nodes are split by the surface area heuristic over kBins bins of the centres along each
        // axis (tighter boxes than median splits where triangle sizes vary, as on CAD parts: fewer
        // boxes lie near a query); by the median along the longest side of the centres' box where
        // no bin boundary splits them, and below depth kSahDepth. Reorders order[begin, end) only.
        auto split = [&](uint32_t begin, uint32_t end, int depth, const std::array<double, 6>& c) {
            uint32_t mid = depth < kSahDepth ? sahSplit(order, begin, end, box, centre, c) : begin;
            if (mid == begin) {
                size_t axis = 0;
                for (size_t a = 1; a < 3; ++a)
                    if (c[a + 3] - c[a] > c[axis + 3] - c[axis]) axis = a;
                mid = begin + (end - begin) / 2;
                std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end, [&](uint32_t x, uint32_t y) {
                    return centre[x][axis] < centre[y][axis] || (centre[x][axis] == centre[y][axis] && x < y);
                });
            }
            return mid;
        };
        // The subtree of order[begin, end) appended to `out` in depth-first order, each inner node's
        // second child counted from out's start. Returns its root's index in `out`.
        auto subtree = [&](auto&& self, std::vector<Node>& out, uint32_t begin, uint32_t end, int depth) -> uint32_t {
            const uint32_t index = uint32_t(out.size());
            out.emplace_back();
            std::array<double, 6> b, c;
            bounds(begin, end, b, c);
            out[index].box = toBox(b);
            if (end - begin <= kLeaf) {
                out[index].first = begin;
                out[index].count = end - begin;
                return index;
            }
            const uint32_t mid = split(begin, end, depth, c);
            self(self, out, begin, mid, depth + 1);  // the first child follows its parent
            const uint32_t second = self(self, out, mid, end, depth + 1);
            out[index].first = second;
            return index;
        };
        // The top levels first, in depth-first order: inner nodes with their boxes, and the
        // subtrees below them as tasks (disjoint ranges of order), built side by side.
        struct Top {
            std::array<double, 6> box;
            size_t task = SIZE_MAX;  // SIZE_MAX: an inner node of the top levels
        };
        std::vector<Top> top;
        std::vector<std::array<uint32_t, 3>> tasks;  // begin, end, depth
        auto plan = [&](auto&& self, uint32_t begin, uint32_t end, int depth) -> void {
            if (depth == kTopDepth || end - begin <= kTopMin) {
                top.push_back({{}, tasks.size()});
                tasks.push_back({begin, end, uint32_t(depth)});
                return;
            }
            std::array<double, 6> b, c;
            bounds(begin, end, b, c);
            top.push_back({b, SIZE_MAX});
            const uint32_t mid = split(begin, end, depth, c);
            self(self, begin, mid, depth + 1);
            self(self, mid, end, depth + 1);
        };
        plan(plan, 0, uint32_t(n), 0);
        std::vector<std::vector<Node>> built(tasks.size());
        parallelFor(tasks.size(), threads, [&](size_t k) {
            built[k].reserve(2 * size_t(tasks[k][1] - tasks[k][0]) / kLeaf + 2);
            subtree(subtree, built[k], tasks[k][0], tasks[k][1], int(tasks[k][2]));
        });
        nodes_.reserve(2 * n / kLeaf + 2);
        size_t next = 0;  // in top
        auto lay = [&](auto&& self) -> uint32_t {
            const Top& t = top[next++];
            const uint32_t index = uint32_t(nodes_.size());
            if (t.task != SIZE_MAX) {
                for (Node node : built[t.task]) {
                    if (node.count == 0) node.first += index;
                    nodes_.push_back(node);
                }
                std::vector<Node>().swap(built[t.task]);
                return index;
            }
            nodes_.emplace_back();
            nodes_[index].box = toBox(t.box);
            self(self);
            const uint32_t second = self(self);
            nodes_[index].first = second;
            return index;
        };
        lay(lay);
        boxes_.resize(n);
        planes_.resize(n);
        parallelChunks(n, kChunk, threads, [&](size_t begin, size_t end, size_t) {
            for (size_t i = begin; i < end; ++i) {
                boxes_[i] = toBox(box[order[i]]);
                planes_[i] = planeOf(triangles[order[i]]);
            }
        });
        input_ = order;
        tieRank_ = order;
    }
};

}  // namespace lodbake::distance_detail
