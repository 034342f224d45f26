// Geometric distance (distance.h). The only translation unit of lodbake that includes CGAL.
//
// Method (Metro, Cignoni, Rocchini, Scopigno 1998): draw area-weighted samples on surface X,
// find each sample's nearest point on surface Y with an AABB tree, and accumulate max, mean and
// RMS; do it both ways. Sampling is stratified along the cumulative area (sample i sits at
// (i + offset) / N of the total area), and the point inside the chosen triangle comes from the R2
// low-discrepancy sequence, so the result is deterministic and converges fast.
#include "lodbake/metrics/distance.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"
#include "metrics/triangle_bvh.h"

namespace lodbake {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleList = std::vector<Triangle>;
using Tree = distance_detail::TriangleBvh;

constexpr size_t kChunk = 4096;  // queries per parallel work item (fixed: results never depend on threads)

Point toPoint(Vec3 p) { return Point(p.x, p.y, p.z); }

// DistanceOptions::stopAbove seen across the work items of one measure: set by the first distance
// above the bound, after which items do no more work (their figures are partial and unused).
class StopAbove {
public:
    explicit StopAbove(double bound) : bound_(bound) {}
    void see(double d) {
        if (d > bound_) hit_.store(true, std::memory_order_relaxed);
    }
    bool hit() const { return hit_.load(std::memory_order_relaxed); }

private:
    double bound_;
    std::atomic<bool> hit_{false};
};

// Non-degenerate triangles of a mesh, as CGAL triangles, with their areas.
struct Surface {
    TriangleList triangles;
    std::vector<uint32_t> faces;         // the mesh face of each triangle
    std::vector<double> cumulativeArea;  // inclusive prefix sums
    std::vector<Vec3> vertices;          // referenced welded positions
};

Surface collectSurface(const TriMesh& m) {
    Surface s;
    // Reserved for every face (degenerate ones are few): a million triangles are 70 MB here, and
    // grown by doubling they would take up to twice that.
    s.triangles.reserve(m.triangles.size());
    s.faces.reserve(m.triangles.size());
    s.cumulativeArea.reserve(m.triangles.size());
    std::vector<uint8_t> used(m.positions.size(), 0);
    double total = 0;
    for (const Tri& t : m.triangles) {
        for (uint32_t v : t) used[v] = 1;
        Vec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
        double area = triangleArea(a, b, c);
        if (!(area > 0) || !std::isfinite(area)) continue;
        Triangle tri(toPoint(a), toPoint(b), toPoint(c));
        if (tri.is_degenerate()) continue;
        s.triangles.push_back(tri);
        s.faces.push_back(uint32_t(&t - m.triangles.data()));
        total += area;
        s.cumulativeArea.push_back(total);
    }
    s.vertices.reserve(size_t(std::count(used.begin(), used.end(), uint8_t(1))));
    for (size_t v = 0; v < used.size(); ++v)
        if (used[v]) s.vertices.push_back(m.positions[v]);
    return s;
}

Vec3 toVec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// A surface with its nearest-point tree, built before any parallel query (the lazy build is not
// thread-safe). Samples are drawn from every triangle of `surface`; the tree holds them less
// coincident copies (withoutCopies: a copy's points are its original's, so no nearest distance
// changes, while k copies would cost a query k times the work), in `distinct` when there are copies.
// It refers to `surface.triangles` or `distinct`, which never move after construction.
struct Measured {
    Surface surface;
    TriangleList distinct;
    Tree tree;
    const TriangleList& held() const { return distinct.empty() ? surface.triangles : distinct; }
    // `threads` build the tree (never changes it).
    Measured(const TriMesh& m, int threads) : surface(collectSurface(m)) {
        if (surface.triangles.empty()) return;
        const std::vector<uint32_t> kept = withoutCopies(m, surface.faces);
        if (kept.size() < surface.faces.size()) {
            distinct.reserve(kept.size());
            for (uint32_t f : kept) {
                const Tri& t = m.triangles[f];
                distinct.emplace_back(toPoint(m.positions[t[0]]), toPoint(m.positions[t[1]]), toPoint(m.positions[t[2]]));
            }
        }
        const TriangleList& held = kept.size() < surface.faces.size() ? distinct : surface.triangles;
        tree = Tree(held, threads);
    }
    Measured(const Measured&) = delete;  // a copy's tree would read the original's triangles
    Measured& operator=(const Measured&) = delete;
};

// Nearest points of consecutive queries on `to`: the previous answer's triangle (q's nearest point
// on it, no farther than the answer c0 itself) bounds the search of the next (samples along a
// surface lie close together). The bound only prunes: the answer is the tree's canonical closest
// point either way.
class NearestWalk {
public:
    explicit NearestWalk(const Tree& tree) : tree_(tree) {}
    Point operator()(const Point& q) { return next(q, hinted_ ? CGAL::squared_distance(q, c0_) : kFar); }
    // ... with `hint`, a point of the surface near q, as a second bound.
    Point operator()(const Point& q, const Point& hint) {
        return next(q, std::min(CGAL::squared_distance(q, hint), hinted_ ? CGAL::squared_distance(q, c0_) : kFar));
    }

private:
    static constexpr double kFar = std::numeric_limits<double>::infinity();
    Point next(const Point& q, double bound2) {
        c0_ = tree_.closest(q, bound2, &t0_);
        hinted_ = true;
        return c0_;
    }
    const Tree& tree_;
    Point c0_{0, 0, 0};
    uint32_t t0_ = UINT32_MAX;  // c0_'s triangle
    bool hinted_ = false;
};

// The i-th of n stratified area samples.
Vec3 samplePoint(const Surface& s, size_t i, size_t n, double offset) {
    double total = s.cumulativeArea.back();
    double target = (static_cast<double>(i) + offset) / static_cast<double>(n) * total;
    size_t t = std::upper_bound(s.cumulativeArea.begin(), s.cumulativeArea.end(), target) - s.cumulativeArea.begin();
    if (t >= s.triangles.size()) t = s.triangles.size() - 1;
    // R2 sequence (Roberts 2018) for the point inside the triangle, folded into the triangle.
    const double g = 1.32471795724474602596;
    double u = fractionalPart(0.5 + double(i + 1) / g);
    double v = fractionalPart(0.5 + double(i + 1) / (g * g));
    if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
    }
    const Vec3 a = toVec(s.triangles[t].vertex(0)), b = toVec(s.triangles[t].vertex(1)), c = toVec(s.triangles[t].vertex(2));
    return a + (b - a) * u + (c - a) * v;
}

OneSidedDistance oneSided(const Surface& from, const Measured& to, const DistanceOptions& o, StopAbove& stop) {
    const size_t n = o.samplesPerSide;
    const size_t total = n + from.vertices.size();
    const double offset = std::fmod(0.5 + 0.6180339887498949 * static_cast<double>(o.seed % 1000003), 1.0);
    const size_t chunks = (total + kChunk - 1) / kChunk;
    struct Partial {
        double max = 0, sum = 0, sum2 = 0;
    };
    std::vector<Partial> partial(chunks);
    parallelFor(chunks, o.threads, [&](size_t c) {
        Partial p;
        if (stop.hit()) return;
        size_t end = std::min(total, (c + 1) * kChunk);
        NearestWalk nearest(to.tree);
        for (size_t i = c * kChunk; i < end; ++i) {
            const Point q = toPoint(i < n ? samplePoint(from, i, n, offset) : from.vertices[i - n]);
            double d = std::sqrt(CGAL::squared_distance(q, nearest(q)));
            p.max = std::max(p.max, d);
            stop.see(d);
            if (i < n) {
                p.sum += d;
                p.sum2 += d * d;
            }
        }
        partial[c] = p;
    });
    OneSidedDistance r;
    double sum = 0, sum2 = 0;
    for (const Partial& p : partial) {  // fixed order: deterministic
        r.max = std::max(r.max, p.max);
        sum += p.sum;
        sum2 += p.sum2;
    }
    if (n > 0) {
        r.mean = sum / static_cast<double>(n);
        r.rms = std::sqrt(sum2 / static_cast<double>(n));
    }
    r.samples = total;
    return r;
}

// oneSided through a coarse pass then a dense pass over the worst runs of samples
// (DistanceOptions::refineStride). Runs are fixed by the sample indices alone: deterministic.
// The coarse pass's samples by place (a uniform grid, cells about the samples' spacing): a bound
// on the distance of any point from the samples near it, d(c) + |p - c| (the distance to a surface
// is 1-Lipschitz).
class CoarseGrid {
public:
    CoarseGrid(const std::vector<Vec3>& points, const std::vector<double>& distance, double spacing)
        : points_(points), distance_(distance) {
        if (points.empty()) return;
        lo_ = hi_ = points[0];
        for (Vec3 p : points) {
            lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y), std::min(lo_.z, p.z)};
            hi_ = {std::max(hi_.x, p.x), std::max(hi_.y, p.y), std::max(hi_.z, p.z)};
        }
        // Cells coarse enough that every cell coordinate fits kBits bits.
        const double extent = std::max({hi_.x - lo_.x, hi_.y - lo_.y, hi_.z - lo_.z});
        cell_ = std::max({spacing, extent / double((1u << kBits) - 2), 1e-300});
        order_.resize(points.size());
        for (uint32_t i = 0; i < points.size(); ++i) order_[i] = {keyOf(cellOf(points[i])), i};
        std::sort(order_.begin(), order_.end());
    }
    // Whether a sample in p's cell or the cells around it bounds p's distance below `limit`. A
    // sample bounds it only from within `limit` of p: a neighbour cell farther away than that
    // (every one when the limit is far below the cells' size, as on a level lying on the
    // original) holds none that could.
    bool boundsBelow(Vec3 p, double limit) const {
        if (order_.empty()) return false;
        const std::array<int64_t, 3> c = cellOf(p);
        const int64_t top = (int64_t(1) << kBits) - 1;
        // p's offsets from its cell's lower and upper walls, per axis.
        const double q[3] = {p.x - lo_.x, p.y - lo_.y, p.z - lo_.z};
        double below[3], above[3];
        for (int a = 0; a < 3; ++a) {
            below[a] = q[a] - double(c[size_t(a)]) * cell_;
            above[a] = double(c[size_t(a)] + 1) * cell_ - q[a];
        }
        for (int k = 0; k < 27; ++k) {  // p's own cell first: its samples are the likeliest to settle it
            const int64_t dx = (k + 13) % 27 / 9 - 1, dy = (k + 13) % 9 / 3 - 1, dz = (k + 13) % 3 - 1;
            const std::array<int64_t, 3> n{c[0] + dx, c[1] + dy, c[2] + dz};
            if (std::min({n[0], n[1], n[2]}) < 0 || std::max({n[0], n[1], n[2]}) > top) continue;
            const int64_t d[3] = {dx, dy, dz};
            double gap2 = 0;  // squared distance from p to the neighbour cell, less a rounding margin
            for (int a = 0; a < 3; ++a) {
                const double g = d[a] < 0 ? below[a] : d[a] > 0 ? above[a] : 0;
                const double m = std::max(0.0, g - 1e-9 * cell_);
                gap2 += m * m;
            }
            if (gap2 >= limit * limit) continue;
            const uint64_t key = keyOf(n);
            auto it = std::lower_bound(order_.begin(), order_.end(), std::make_pair(key, uint32_t(0)));
            for (; it != order_.end() && it->first == key; ++it)
                if (distance_[it->second] + length(p - points_[it->second]) < limit) return true;
        }
        return false;
    }

private:
    static constexpr int kBits = 20;
    std::array<int64_t, 3> cellOf(Vec3 p) const {
        return {int64_t(std::floor((p.x - lo_.x) / cell_)), int64_t(std::floor((p.y - lo_.y) / cell_)),
                int64_t(std::floor((p.z - lo_.z) / cell_))};
    }
    static uint64_t keyOf(const std::array<int64_t, 3>& c) {
        return (uint64_t(c[0]) << (2 * kBits)) | (uint64_t(c[1]) << kBits) | uint64_t(c[2]);
    }
    const std::vector<Vec3>& points_;
    const std::vector<double>& distance_;
    Vec3 lo_{}, hi_{};
    double cell_ = 1;
    std::vector<std::pair<uint64_t, uint32_t>> order_;  // (cell key, sample) sorted
};

// The largest distance of `from`'s vertices to `to` where it reaches `coarseMax` (a maximum the
// area samples reach): a vertex contributes only to the maximum, so one that a coarse sample of
// `grid` (null: none) bounds below coarseMax is not queried. `queried` counts the queries.
double vertexMaximum(const Surface& from, const Measured& to, const CoarseGrid* grid, double coarseMax, int threads,
                     StopAbove& stop, size_t& queried) {
    const size_t nv = from.vertices.size(), items = (nv + kChunk - 1) / kChunk;
    const double limit = coarseMax * (1 - 1e-9);  // margin for rounding
    std::vector<double> itemMax(items, 0.0);
    std::vector<size_t> itemQueried(items, 0);
    parallelFor(items, threads, [&](size_t c) {
        NearestWalk nearest(to.tree);  // vertices of nearby ids mostly lie near each other
        for (size_t v = c * kChunk; v < std::min(nv, (c + 1) * kChunk) && !stop.hit(); ++v) {
            const Vec3 p = from.vertices[v];
            if (grid && grid->boundsBelow(p, limit)) continue;
            const double d = std::sqrt(CGAL::squared_distance(toPoint(p), nearest(toPoint(p))));
            itemMax[c] = std::max(itemMax[c], d);
            stop.see(d);
            ++itemQueried[c];
        }
    });
    double m = 0;
    queried = 0;
    for (size_t c = 0; c < items; ++c) {
        m = std::max(m, itemMax[c]);
        queried += itemQueried[c];
    }
    return m;
}

OneSidedDistance oneSidedRefined(const Surface& from, const Measured& to, const DistanceOptions& o, StopAbove& stop) {
    const size_t n = o.samplesPerSide, stride = o.refineStride;
    const double offset = std::fmod(0.5 + 0.6180339887498949 * static_cast<double>(o.seed % 1000003), 1.0);
    const size_t blocks = (n + kRefineBlock - 1) / kRefineBlock;
    const size_t blocksPerItem = std::max<size_t>(1, kChunk / kRefineBlock);
    const size_t sampleItems = (blocks + blocksPerItem - 1) / blocksPerItem;
    struct Partial {
        double max = 0, sum = 0, sum2 = 0;
        size_t count = 0;
    };
    std::vector<Partial> partial(sampleItems);
    std::vector<double> blockMax(blocks, 0.0);
    std::vector<double> coarse((n + stride - 1) / stride, 0.0);  // distance of every strided sample
    std::vector<Vec3> coarsePoint(coarse.size());                // and where it lies
    parallelFor(sampleItems, o.threads, [&](size_t c) {
        Partial p;
        for (size_t b = c * blocksPerItem; b < std::min(blocks, (c + 1) * blocksPerItem) && !stop.hit(); ++b) {
            const size_t first = (b * kRefineBlock + stride - 1) / stride * stride;  // first strided index
            NearestWalk nearest(to.tree);
            for (size_t i = first; i < std::min(n, (b + 1) * kRefineBlock); i += stride) {
                coarsePoint[i / stride] = samplePoint(from, i, n, offset);
                const Point q = toPoint(coarsePoint[i / stride]);
                const double d = std::sqrt(CGAL::squared_distance(q, nearest(q)));
                coarse[i / stride] = d;
                blockMax[b] = std::max(blockMax[b], d);
                stop.see(d);
                p.sum += d;
                p.sum2 += d * d;
                ++p.count;
            }
            p.max = std::max(p.max, blockMax[b]);
        }
        partial[c] = p;
    });
    OneSidedDistance r;
    double sum = 0, sum2 = 0;
    size_t count = 0;
    for (const Partial& p : partial) {  // fixed order: deterministic
        r.max = std::max(r.max, p.max);
        sum += p.sum;
        sum2 += p.sum2;
        count += p.count;
    }
    size_t vertexQueries = 0;
    if (stop.hit()) return r;
    {
        // The grid pays off only when the vertices outnumber a fair share of the coarse samples;
        // without it every vertex is queried: the maximum is the same either way.
        std::optional<CoarseGrid> grid;
        if (4 * from.vertices.size() >= coarse.size()) {
            const double spacing = std::sqrt(from.cumulativeArea.back() / double(std::max<size_t>(1, coarse.size())));
            grid.emplace(coarsePoint, coarse, 2 * spacing);
        }
        r.max = std::max(r.max, vertexMaximum(from, to, grid ? &*grid : nullptr, r.max, o.threads, stop, vertexQueries));
    }
    if (stop.hit()) return r;
    const double threshold = o.refineFraction * std::max(r.max, o.refineFloor);
    std::vector<size_t> hot;
    for (size_t b = 0; b < blocks; ++b)
        if (blockMax[b] >= threshold) hot.push_back(b);
    // A sample of a run is queried only when it could exceed the coarse maximum or refineFloor: the
    // distance is 1-Lipschitz, so a strided sample c of the run bounds it by d(c) + |p - c| (with a
    // margin for rounding). The maximum is the dense one exactly wherever it reaches refineFloor,
    // with far fewer queries where a coarse level lies far from the original everywhere.
    const double known = std::max(r.max, o.refineFloor) * (1 - 1e-9);
    std::vector<double> hotMax(hot.size(), 0.0);
    std::vector<size_t> hotQueried(hot.size(), 0);
    parallelFor(hot.size(), o.threads, [&](size_t h) {
        if (stop.hit()) return;
        const size_t b = hot[h], begin = b * kRefineBlock, end = std::min(n, begin + kRefineBlock);
        std::vector<std::pair<Vec3, double>> strided;  // the run's strided samples and their distances
        for (size_t i = (begin + stride - 1) / stride * stride; i < end; i += stride)
            strided.emplace_back(samplePoint(from, i, n, offset), coarse[i / stride]);
        NearestWalk nearest(to.tree);
        for (size_t i = begin; i < end; ++i) {
            if (i % stride == 0) continue;
            const Vec3 p = samplePoint(from, i, n, offset);
            double bound = 1e300;
            for (const auto& [c, d] : strided) bound = std::min(bound, d + length(p - c));
            if (bound < known) continue;
            const Point q = toPoint(p);
            const double d = std::sqrt(CGAL::squared_distance(q, nearest(q)));
            hotMax[h] = std::max(hotMax[h], d);
            stop.see(d);
            ++hotQueried[h];
        }
    });
    for (double m : hotMax) r.max = std::max(r.max, m);
    if (count > 0) {
        r.mean = sum / static_cast<double>(count);
        r.rms = std::sqrt(sum2 / static_cast<double>(count));
    }
    r.samples = count + vertexQueries;
    for (size_t q : hotQueried) r.samples += q;
    return r;
}

OneSidedDistance measureSide(const Surface& from, const Measured& to, const DistanceOptions& o, StopAbove& stop) {
    return o.refineStride > 1 && o.samplesPerSide > 0 ? oneSidedRefined(from, to, o, stop) : oneSided(from, to, o, stop);
}

}  // namespace

using CgalPrimitive = CGAL::AABB_triangle_primitive<Kernel, TriangleList::const_iterator>;
using CgalTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CgalPrimitive>>;

// Traversal traits that visit every primitive of a CGAL tree, numbering them in visiting order.
struct VisitAll {
    const Triangle* first;
    std::vector<uint32_t>& rank;
    uint32_t next = 0;
    bool go_further() const { return true; }
    void intersection(const Point&, const CgalPrimitive& p) { rank[size_t(&*p.id() - first)] = next++; }
    template <class Node>
    bool do_intersect(const Point&, const Node&) const { return true; }
};

// The order in which CGAL's AABB tree over `triangles` visits them (its primitives' order after
// its build; only the build runs, no query). Of equally close points, that tree's closest_point
// returns the last one it visits (a point replaces the best so far unless it is farther), so the
// triangles ranked by this order break ties as it does: the closest points are that tree's.
std::vector<uint32_t> cgalVisitRanks(const TriangleList& triangles) {
    std::vector<uint32_t> rank(triangles.size(), 0);
    if (triangles.empty()) return rank;
    const CgalTree tree(triangles.begin(), triangles.end());
    VisitAll visit{triangles.data(), rank};
    tree.traversal(Point(0, 0, 0), visit);
    return rank;
}

struct DistanceReference::Prepared {
    Measured measured;
    double diagonal = 0;
    Prepared(const TriMesh& a, int threads) : measured(a, threads), diagonal(bounds(a).diagonal()) {}
    // closestPoint(s) answer points, not only distances: their ties are broken as CGAL's tree
    // over the same triangles breaks them, ranked before the first query.
    std::once_flag ranked;
    const Tree& rankedTree() {
        std::call_once(ranked, [&] { measured.tree.setTieRanks(cgalVisitRanks(measured.held())); });
        return measured.tree;
    }
};

DistanceReference::DistanceReference(const TriMesh& a, int threads) : prepared_(std::make_unique<Prepared>(a, threads)) {
    if (prepared_->measured.surface.triangles.empty()) throw Impossible("first mesh has no triangle with non-zero area");
}
DistanceReference::~DistanceReference() = default;
DistanceReference::DistanceReference(DistanceReference&&) noexcept = default;
DistanceReference& DistanceReference::operator=(DistanceReference&&) noexcept = default;

Vec3 DistanceReference::closestPoint(Vec3 p) const { return toVec(prepared_->rankedTree().closest(toPoint(p))); }

std::vector<Vec3> DistanceReference::closestPoints(const std::vector<Vec3>& points, int threads, const std::vector<Vec3>& near) const {
    const Tree& tree = prepared_->rankedTree();
    std::vector<Vec3> out(points.size());
    parallelFor((points.size() + kChunk - 1) / kChunk, threads, [&](size_t c) {
        NearestWalk nearest(tree);
        for (size_t i = c * kChunk; i < std::min(points.size(), (c + 1) * kChunk); ++i) {
            const Point q = toPoint(points[i]);
            out[i] = toVec(i < near.size() && !std::isnan(near[i].x) ? nearest(q, toPoint(near[i])) : nearest(q));
        }
    });
    return out;
}

GeometricDistance surfaceDistance(const DistanceReference& reference, const TriMesh& b, const DistanceOptions& options) {
    const Measured& ma = reference.prepared().measured;
    const Measured mb(b, options.threads);
    if (mb.surface.triangles.empty()) throw Impossible("second mesh has no triangle with non-zero area");

    GeometricDistance r;
    StopAbove stop(options.stopAbove);
    r.aToB = measureSide(ma.surface, mb, options, stop);
    if (!stop.hit()) {
        DistanceOptions second = options;
        second.refineFloor = std::max(options.refineFloor, r.aToB.max);
        r.bToA = measureSide(mb.surface, ma, second, stop);
    }
    r.stopped = stop.hit();
    r.hausdorff = std::max(r.aToB.max, r.bToA.max);
    r.mean = 0.5 * (r.aToB.mean + r.bToA.mean);
    r.rms = std::sqrt(0.5 * (r.aToB.rms * r.aToB.rms + r.bToA.rms * r.bToA.rms));
    r.diagonal = reference.prepared().diagonal;
    if (r.diagonal > 0) {
        r.relHausdorff = r.hausdorff / r.diagonal;
        r.relMean = r.mean / r.diagonal;
        r.relRms = r.rms / r.diagonal;
    }
    return r;
}

GeometricDistance surfaceDistance(const TriMesh& a, const TriMesh& b, const DistanceOptions& options) {
    return surfaceDistance(DistanceReference(a, options.threads), b, options);
}

}  // namespace lodbake
