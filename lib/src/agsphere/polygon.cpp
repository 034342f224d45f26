// Planar polygon triangulation for agsphere-build: simplicity check, hole bridging, ear clipping.
//
// Pipeline, in execution order:
//   polygonIsSimple     segment-segment tests through a uniform grid (near-linear)
//   bridgeHoles         each hole joined to the outer loop by a visible diagonal (two duplicated
//                       nodes), holes with the rightmost vertex first
//   clipEars            the thesis's scan (2.4.4, Figure 31): a convex vertex whose triangle holds
//                       no other node is cut off and the scan steps back to the previous vertex;
//                       point-in-triangle queries go through a grid of the live nodes
// Validity does not rest on the ear test: an ear is only cut when its area is strictly positive,
// and the ears' boundary chains always sum to the polygon's, so a run that completes on a simple
// polygon is a tiling (see polygon.h). The ear test only keeps the scan from getting stuck.
#include "lodbake/agsphere/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/grid2d.h"

namespace lodbake {
namespace {

double orient(Vec2 a, Vec2 b, Vec2 c) { return cross(b - a, c - a); }

bool onSegment(Vec2 a, Vec2 b, Vec2 p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

int sign(double v) { return (v > 0) - (v < 0); }

// Closed segment intersection (touching counts).
bool segmentsMeet(Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2) {
    int d1 = sign(orient(q1, q2, p1)), d2 = sign(orient(q1, q2, p2));
    int d3 = sign(orient(p1, p2, q1)), d4 = sign(orient(p1, p2, q2));
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;
    if (d1 == 0 && onSegment(q1, q2, p1)) return true;
    if (d2 == 0 && onSegment(q1, q2, p2)) return true;
    if (d3 == 0 && onSegment(p1, p2, q1)) return true;
    if (d4 == 0 && onSegment(p1, p2, q2)) return true;
    return false;
}

struct Bounds2 {
    Vec2 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    Vec2 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    void extend(Vec2 p) {
        min = {std::min(min.x, p.x), std::min(min.y, p.y)};
        max = {std::max(max.x, p.x), std::max(max.y, p.y)};
    }
};

// A grid of about one cell per item over `box` (core/grid2d.h).
Grid2 gridOver(const Bounds2& box, const std::vector<GridItem2>& items) {
    const std::array<int, 2> n = Grid2::squareCells(box.min, box.max, items.size());
    return Grid2(box.min, box.max, n[0], n[1], items);
}

double loopArea(const PlanarPolygon& poly, const std::vector<uint32_t>& loop) {
    double a = 0;
    for (size_t i = 0; i < loop.size(); ++i)
        a += cross(poly.points[loop[i]], poly.points[loop[(i + 1) % loop.size()]]);
    return 0.5 * a;
}

// Linked-list node of the merged loop.
struct Node {
    uint32_t id;
    Vec2 p;
    uint32_t prev, next;
    bool alive = true;
};

struct Ring {
    std::vector<Node> nodes;
    uint32_t add(uint32_t id, Vec2 p) {
        nodes.push_back({id, p, uint32_t(nodes.size()), uint32_t(nodes.size()), true});
        return uint32_t(nodes.size() - 1);
    }
};

// Whether direction d from node a points into the polygon's interior at a (interior on the left
// of a counter-clockwise boundary).
bool locallyInside(const Ring& r, uint32_t a, Vec2 target) {
    const Node& n = r.nodes[a];
    Vec2 p = r.nodes[n.prev].p, q = r.nodes[n.next].p, o = n.p;
    Vec2 d = target - o;
    if (orient(p, o, q) >= 0)  // convex (or straight)
        return cross(q - o, d) > 0 && cross(d, p - o) > 0;
    return !(cross(p - o, d) >= 0 && cross(d, q - o) >= 0);
}

// Joins hole loops into the outer ring. Returns false when a hole finds no visible partner.
bool bridgeHoles(const PlanarPolygon& poly, size_t outer, Ring& ring, uint32_t& start) {
    auto makeLoop = [&](const std::vector<uint32_t>& loop) {
        uint32_t first = uint32_t(ring.nodes.size());
        for (uint32_t id : loop) ring.add(id, poly.points[id]);
        uint32_t n = uint32_t(loop.size());
        for (uint32_t i = 0; i < n; ++i) {
            ring.nodes[first + i].next = first + (i + 1) % n;
            ring.nodes[first + i].prev = first + (i + n - 1) % n;
        }
        return first;
    };
    start = makeLoop(poly.loops[outer]);
    std::vector<std::pair<uint32_t, size_t>> holes;  // (first node, loop index)
    for (size_t l = 0; l < poly.loops.size(); ++l)
        if (l != outer) holes.push_back({makeLoop(poly.loops[l]), l});
    // Rightmost vertex of each hole; holes with the rightmost vertex go first.
    std::vector<std::pair<uint32_t, double>> order;
    for (auto& [first, l] : holes) {
        uint32_t best = first;
        for (uint32_t k = 0; k < poly.loops[l].size(); ++k) {
            const Node& n = ring.nodes[first + k];
            const Node& b = ring.nodes[best];
            if (n.p.x > b.p.x || (n.p.x == b.p.x && n.p.y < b.p.y)) best = first + k;
        }
        order.push_back({best, ring.nodes[best].p.x});
    }
    std::stable_sort(order.begin(), order.end(), [](auto& a, auto& b) { return a.second > b.second; });
    std::vector<char> merged(ring.nodes.size(), 0);
    for (uint32_t i = start;;) {
        merged[i] = 1;
        i = ring.nodes[i].next;
        if (i == start) break;
    }
    for (size_t hi = 0; hi < order.size(); ++hi) {
        uint32_t h = order[hi].first;
        Vec2 hp = ring.nodes[h].p;
        // Candidates: merged nodes by distance to h.
        std::vector<std::pair<double, uint32_t>> cand;
        for (uint32_t i = 0; i < ring.nodes.size(); ++i)
            if (merged[i] && ring.nodes[i].alive) { Vec2 d = ring.nodes[i].p - hp; cand.push_back({dot(d, d), i}); }
        std::sort(cand.begin(), cand.end());
        uint32_t found = UINT32_MAX;
        for (auto& [d2, o] : cand) {
            (void)d2;
            if (ring.nodes[o].id != ring.nodes[h].id) {
                if (!locallyInside(ring, o, hp) || !locallyInside(ring, h, ring.nodes[o].p)) continue;
            }
            Vec2 op = ring.nodes[o].p;
            bool blocked = false;
            // Against every segment of the ring nodes (merged ones and all holes).
            for (uint32_t i = 0; i < ring.nodes.size() && !blocked; ++i) {
                const Node& a = ring.nodes[i];
                const Node& b = ring.nodes[a.next];
                uint32_t ids[2] = {a.id, b.id};
                bool touchesEnd = false;
                for (uint32_t id : ids) touchesEnd |= id == ring.nodes[o].id || id == ring.nodes[h].id;
                if (touchesEnd) continue;
                if (segmentsMeet(op, hp, a.p, b.p)) blocked = true;
            }
            if (!blocked) {
                found = o;
                break;
            }
        }
        if (found == UINT32_MAX) return false;
        // o -> h ... (hole) ... h2 -> o2 -> old next of o.
        uint32_t o = found;
        uint32_t h2 = ring.add(ring.nodes[h].id, hp);
        uint32_t o2 = ring.add(ring.nodes[o].id, ring.nodes[o].p);
        merged.resize(ring.nodes.size(), 0);
        uint32_t oNext = ring.nodes[o].next, hPrev = ring.nodes[h].prev;
        ring.nodes[o].next = h;
        ring.nodes[h].prev = o;
        ring.nodes[hPrev].next = h2;
        ring.nodes[h2].prev = hPrev;
        ring.nodes[h2].next = o2;
        ring.nodes[o2].prev = h2;
        ring.nodes[o2].next = oNext;
        ring.nodes[oNext].prev = o2;
        for (uint32_t i = h;;) {
            merged[i] = 1;
            i = ring.nodes[i].next;
            if (i == o2) break;
        }
        merged[o2] = 1;
    }
    return true;
}

bool pointInTriangle(Vec2 a, Vec2 b, Vec2 c, Vec2 p) {
    return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

bool clipEars(Ring& ring, uint32_t start, std::vector<Tri>& out, const std::function<bool(uint32_t, uint32_t)>& allow,
              const std::function<bool(uint32_t, uint32_t, uint32_t)>& allowTriangle) {
    size_t count = 0;
    Bounds2 box;
    for (uint32_t i = start;;) {
        ++count;
        box.extend(ring.nodes[i].p);
        i = ring.nodes[i].next;
        if (i == start) break;
    }
    if (count < 3) return false;
    const double scale = std::max(box.max.x - box.min.x, box.max.y - box.min.y);
    const double minArea = 1e-14 * scale * scale;
    std::vector<GridItem2> nodes;
    std::unordered_map<uint64_t, uint32_t> edges;  // current ring edges (undirected id pairs)
    for (uint32_t i = start;;) {
        nodes.push_back({i, ring.nodes[i].p, ring.nodes[i].p});
        ++edges[edgeKey(ring.nodes[i].id, ring.nodes[ring.nodes[i].next].id)];
        i = ring.nodes[i].next;
        if (i == start) break;
    }
    const Grid2 grid = gridOver(box, nodes);
    auto isEar = [&](uint32_t c) {
        const Node& N = ring.nodes[c];
        const Node& P = ring.nodes[N.prev];
        const Node& X = ring.nodes[N.next];
        if (orient(P.p, N.p, X.p) <= minArea) return false;
        if (count > 3) {
            auto it = edges.find(edgeKey(P.id, X.id));
            if (it != edges.end() && it->second > 0) return false;
            if (allow && !allow(P.id, X.id)) return false;
        }
        if (allowTriangle && !allowTriangle(P.id, N.id, X.id)) return false;
        Vec2 lo{std::min({P.p.x, N.p.x, X.p.x}), std::min({P.p.y, N.p.y, X.p.y})};
        Vec2 hi{std::max({P.p.x, N.p.x, X.p.x}), std::max({P.p.y, N.p.y, X.p.y})};
        bool blocked = false;
        grid.visit(lo, hi, [&](const Grid2::Cell& cell) {
            for (uint32_t k : cell) {
                if (blocked) return;
                const Node& K = ring.nodes[k];
                if (!K.alive || K.id == P.id || K.id == N.id || K.id == X.id) continue;
                if (pointInTriangle(P.p, N.p, X.p, K.p)) blocked = true;
            }
        });
        return !blocked;
    };
    std::vector<Tri> tris;
    tris.reserve(count - 2);
    uint32_t cur = start;
    size_t sinceClip = 0;
    while (count > 3) {
        if (isEar(cur)) {
            Node& N = ring.nodes[cur];
            tris.push_back({ring.nodes[N.prev].id, N.id, ring.nodes[N.next].id});
            --edges[edgeKey(ring.nodes[N.prev].id, N.id)];
            --edges[edgeKey(N.id, ring.nodes[N.next].id)];
            ++edges[edgeKey(ring.nodes[N.prev].id, ring.nodes[N.next].id)];
            N.alive = false;
            ring.nodes[N.prev].next = N.next;
            ring.nodes[N.next].prev = N.prev;
            --count;
            cur = N.prev;  // step back (thesis: v_{i-1} becomes current)
            sinceClip = 0;
            continue;
        }
        cur = ring.nodes[cur].next;
        if (++sinceClip > count) return false;
    }
    const Node& N = ring.nodes[cur];
    if (orient(ring.nodes[N.prev].p, N.p, ring.nodes[N.next].p) <= minArea) return false;
    if (allowTriangle && !allowTriangle(ring.nodes[N.prev].id, N.id, ring.nodes[N.next].id)) return false;
    tris.push_back({ring.nodes[N.prev].id, N.id, ring.nodes[N.next].id});
    out.insert(out.end(), tris.begin(), tris.end());
    return true;
}

}  // namespace

bool polygonIsSimple(const PlanarPolygon& poly) {
    int positive = 0;
    size_t segs = 0;
    for (const auto& loop : poly.loops) {
        if (loop.size() < 3) return false;
        double a = loopArea(poly, loop);
        if (a > 0) ++positive;
        else if (!(a < 0)) return false;
        segs += loop.size();
    }
    if (positive != 1) return false;
    struct Seg {
        uint32_t a, b;
    };
    std::vector<Seg> s;
    s.reserve(segs);
    Bounds2 box;
    for (const auto& loop : poly.loops)
        for (size_t i = 0; i < loop.size(); ++i) {
            s.push_back({loop[i], loop[(i + 1) % loop.size()]});
            box.extend(poly.points[loop[i]]);
        }
    for (const Seg& g : s)
        if (g.a == g.b) return false;
    std::vector<GridItem2> segments;
    for (uint32_t i = 0; i < s.size(); ++i) {
        Vec2 p = poly.points[s[i].a], q = poly.points[s[i].b];
        segments.push_back({i, {std::min(p.x, q.x), std::min(p.y, q.y)}, {std::max(p.x, q.x), std::max(p.y, q.y)}});
    }
    const Grid2 grid = gridOver(box, segments);
    for (int cy = 0; cy < grid.ny(); ++cy)
        for (int cx = 0; cx < grid.nx(); ++cx) {
            const Grid2::Cell cell = grid.cell(cx, cy);
            for (size_t x = 0; x < cell.size(); ++x)
                for (size_t y = x + 1; y < cell.size(); ++y) {
                    const Seg& g = s[cell.first[x]];
                    const Seg& h = s[cell.first[y]];
                    Vec2 p1 = poly.points[g.a], p2 = poly.points[g.b], q1 = poly.points[h.a], q2 = poly.points[h.b];
                    int shared = (g.a == h.a) + (g.a == h.b) + (g.b == h.a) + (g.b == h.b);
                    if (shared >= 2) return false;  // repeated segment (or a spike a -> b -> a)
                    if (shared == 1) {
                        // Meeting at the shared id is fine unless the two segments overlap.
                        uint32_t common = (g.a == h.a || g.a == h.b) ? g.a : g.b;
                        Vec2 c = poly.points[common];
                        Vec2 u = (g.a == common ? p2 : p1) - c, v = (h.a == common ? q2 : q1) - c;
                        if (cross(u, v) == 0 && dot(u, v) > 0) return false;
                        continue;
                    }
                    if (segmentsMeet(p1, p2, q1, q2)) return false;
                }
        }
    return true;
}

bool triangulatePolygon(const PlanarPolygon& poly, std::vector<Tri>& out,
                        const std::function<bool(uint32_t, uint32_t)>& allowDiagonal,
                        const std::function<bool(uint32_t, uint32_t, uint32_t)>& allowTriangle) {
    if (poly.loops.empty()) return false;
    size_t outer = SIZE_MAX;
    for (size_t l = 0; l < poly.loops.size(); ++l) {
        if (poly.loops[l].size() < 3) return false;
        if (loopArea(poly, poly.loops[l]) > 0) {
            if (outer != SIZE_MAX) return false;
            outer = l;
        }
    }
    if (outer == SIZE_MAX) return false;
    Ring ring;
    uint32_t start = 0;
    if (!bridgeHoles(poly, outer, ring, start)) return false;
    return clipEars(ring, start, out, allowDiagonal, allowTriangle);
}

}  // namespace lodbake
